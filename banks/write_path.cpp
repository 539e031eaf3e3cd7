#include "banks/write_path.hpp"

namespace unima::banks {

modbus::WriteResult WritePath::write_registers(std::uint16_t first, std::span<const std::uint16_t> values,
                                               const modbus::WriteRights* rights) {
  using Status = modbus::WriteResult::Status;
  if (frozen_) return {Status::read_only};
  // SPEC §11: the rights come before the address is looked at, so a client without the
  // right learns nothing of the map.
  if (rights && !rights->allows(first, static_cast<std::uint16_t>(values.size()))) return {Status::not_allowed};
  modbus::WriteResult result;
  const bool written = space_.write(first, values, [&](BankId bank, std::uint16_t offset, std::uint16_t value) {
    if (journal_) result.kept_as = journal_->keep(bank, offset, value);
  });
  if (!written) return {Status::not_writable};
  return result;
}

modbus::WriteResult WritePath::write_bit(std::uint16_t address, unsigned bit, bool on, const modbus::WriteRights* rights) {
  std::uint16_t value = 0;
  // A write-only register (W and X without readable_write_banks) still has its bits: the
  // store holds them whatever Modbus may read.
  if (const auto* window = space_.map().find(address); window && window->kind == Window::Kind::bank)
    value = space_.store().read(window->bank, static_cast<std::uint16_t>(address - window->first));
  const auto mask = static_cast<std::uint16_t>(1u << bit);
  value = on ? static_cast<std::uint16_t>(value | mask) : static_cast<std::uint16_t>(value & ~mask);
  return write_registers(address, std::span(&value, 1), rights);
}

}  // namespace unima::banks
