#include "banks/write_path.hpp"

namespace unima::banks {

modbus::WriteResult WritePath::write_registers(std::uint16_t first, std::span<const std::uint16_t> values,
                                               const modbus::WriteRights* rights) {
  using Status = modbus::WriteResult::Status;
  if (frozen_) return {Status::read_only};
  // SPEC §11: the rights come before the address is looked at, so a client without the
  // right learns nothing of the map.
  if (rights && !rights->allows(first, static_cast<std::uint16_t>(values.size()))) return {Status::not_allowed};
  if (!journal_) {
    if (!space_.resolve(first, values, [this](const WrittenValue& value) { apply(value); })) return {Status::not_writable};
    return {};
  }
  resolved_.clear();
  if (!space_.resolve(first, values, [this](const WrittenValue& value) { resolved_.push_back(value); }))
    return {Status::not_writable};
  return {Status::written, journal_->keep(resolved_)};
}

modbus::WriteResult WritePath::write_bit(std::uint16_t address, unsigned bit, bool on, const modbus::WriteRights* rights) {
  const auto mask = static_cast<std::uint16_t>(1u << bit);
  return write_field(address, mask, on ? mask : 0, rights);
}

modbus::WriteResult WritePath::write_field(std::uint16_t address, std::uint16_t mask, std::uint16_t bits,
                                           const modbus::WriteRights* rights) {
  std::uint16_t value = 0;
  // A write-only register (W and X without readable_write_banks) still has its bits: the
  // store holds them whatever Modbus may read.
  if (const auto* window = space_.map().find(address); window && window->kind == Window::Kind::bank) {
    const auto offset = static_cast<std::uint16_t>(address - window->first);
    const auto pending = journal_ ? journal_->pending(window->bank, offset) : std::nullopt;
    value = pending ? *pending : space_.store().read(window->bank, offset);
  }
  value = static_cast<std::uint16_t>((value & ~mask) | (bits & mask));
  return write_registers(address, std::span(&value, 1), rights);
}

void WritePath::commit(std::span<const WrittenValue> write) {
  const auto& store = space_.store();
  for (const auto& value : write)
    if (value.offset < store.length(value.bank)) apply(value);
}

void WritePath::apply(const WrittenValue& value) {
  auto& store = space_.store();
  if (value.bank == BankId::C)
    store.set_user_output(value.offset - c_bank::user_analog_outputs + 1u, value.value);
  else
    store.write(value.bank, value.offset, value.value);
}

}  // namespace unima::banks
