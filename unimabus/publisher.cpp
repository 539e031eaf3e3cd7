#include "unimabus/publisher.hpp"

#include "unimabus/feed_codec.hpp"

namespace unima::unimabus {

using banks::BankId;

void Publisher::watch(banks::RegisterStore& store) {
  store_ = &store;
  store.set_change_listener([this](BankId bank, std::uint16_t offset, std::uint16_t value) {
    if (transport_) transport_->publish(bank, offset, value);
  });
}

std::string Publisher::snapshot() const {
  std::string lines;
  if (!store_) return lines;
  // A W or X register no master has written is left out: a driver must never take the
  // 0x7FFF or 0 it reads for a setpoint (SPEC §10).
  const auto written_of = [&](BankId bank) {
    for (std::uint16_t i = 0; i < store_->length(bank); ++i)
      if (store_->written(bank, i)) lines += format_change(bank, i, store_->read(bank, i));
  };
  written_of(BankId::W);
  written_of(BankId::X);
  for (std::uint16_t i = 0; i <= banks::c_bank::user_binary_outputs; ++i)
    lines += format_change(BankId::C, i, store_->read(BankId::C, i));
  return lines;
}

}  // namespace unima::unimabus
