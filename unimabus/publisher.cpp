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
  const auto all_of = [&](BankId bank, std::uint16_t count) {
    for (std::uint16_t i = 0; i < count; ++i) lines += format_change(bank, i, store_->read(bank, i));
  };
  all_of(BankId::W, store_->length(BankId::W));
  all_of(BankId::X, store_->length(BankId::X));
  all_of(BankId::C, banks::c_bank::user_binary_outputs + 1);
  return lines;
}

}  // namespace unima::unimabus
