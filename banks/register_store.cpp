#include "banks/register_store.hpp"

#include <algorithm>
#include <utility>

namespace unima::banks {

BankShapes standard_shapes(const std::array<const DeviceTable*, 4>& device_tables, const DeviceTable* io_module,
                           const DeviceTable* bridge_internal) {
  BankShapes shapes{};
  shapes[index_of(BankId::A)] = {analog_bank_length, nullptr};
  shapes[index_of(BankId::B)] = {bit_bank_length, nullptr};
  shapes[index_of(BankId::C)] = {c_bank_length, bridge_internal};
  shapes[index_of(BankId::W)] = {analog_bank_length, nullptr};
  shapes[index_of(BankId::X)] = {bit_bank_length, nullptr};
  for (unsigned n = 1; n <= 7; ++n) shapes[index_of(module_bank(n))] = {s_bank_length, io_module};
  for (unsigned n = 1; n <= 4; ++n) {
    const auto* table = device_tables[n - 1];
    shapes[index_of(device_bank(n))] = {table ? device_bank_length : std::uint16_t{0}, table};
  }
  return shapes;
}

RegisterStore::RegisterStore(const BankShapes& shapes) : shapes_(shapes) {
  for (BankId id : all_banks) {
    const auto& shape = shapes[index_of(id)];
    auto& bank = bank_(id);
    bank.length = shape.length;
    bank.filled_length = banks::filled_length(shape);
    bank.offline.assign(shape.length, not_measured);
    if (shape.table)
      for (const auto& reg : shape.table->registers)
        if (reg.offset < shape.length) bank.offline[reg.offset] = offline_value(reg.kind);
    if (id == BankId::B || id == BankId::X) bank.offline.assign(shape.length, 0);
    bank.raw = bank.offline;
    bank.served = bank.offline;
    bank.carried.assign(shape.length, 0);
  }
}

void RegisterStore::refresh_served(Bank& bank, std::size_t from, std::size_t count) {
  for (std::size_t r = from; r < from + count; ++r)
    bank.served[r] = bank.online && bank.carried[r] ? bank.raw[r] : bank.offline[r];
}

void RegisterStore::read(BankId id, std::uint16_t offset, std::span<std::uint16_t> out) const {
  const auto& bank = bank_(id);
  if (is_device_bank(id) || is_module_bank(id)) {
    std::copy_n(bank.served.begin() + offset, out.size(), out.begin());
    return;
  }
  switch (id) {
    case BankId::A:
      // Not measured, whatever the source's kind, while the source is not (SPEC §1).
      for (std::size_t i = 0; i < out.size(); ++i) {
        const auto& source = mapping_.analog[offset + i];
        out[i] = source && measured(source->bank, source->offset)
                     ? to_tenths(read(source->bank, source->offset), analog_conversions_[offset + i])
                     : not_measured;
      }
      return;
    case BankId::B: out[0] = mapped_bits(mapping_.bits); return;
    case BankId::C:
      for (std::size_t i = 0; i < out.size(); ++i) {
        const std::size_t r = offset + i;
        if (r == c_bank::user_binary_inputs) out[i] = mapped_bits(mapping_.user_inputs);
        else if (r == c_bank::user_binary_outputs) out[i] = mapped_bits(mapping_.user_outputs);
        else if (r == c_bank::online_bits) out[i] = online_bits();
        else if (r > c_bank::user_binary_inputs) out[i] = 0;  // +0x11 reserve
        else out[i] = bank.raw[r];
      }
      return;
    default: std::copy_n(bank.raw.begin() + offset, out.size(), out.begin());
  }
}

bool RegisterStore::measured(BankId id, std::uint16_t offset) const {
  const auto& bank = bank_(id);
  if (is_device_bank(id) || is_module_bank(id)) return bank.online && bank.carried[offset];
  if (id == BankId::A) return mapping_.analog[offset] && measured(mapping_.analog[offset]->bank, mapping_.analog[offset]->offset);
  return true;
}

void RegisterStore::set_mapping(const Mapping& mapping) {
  mapping_ = mapping;
  for (std::size_t n = 0; n < Mapping::entries; ++n) {
    const auto& source = mapping_.analog[n];
    const auto* table = source ? shapes_[index_of(source->bank)].table : nullptr;
    const auto* reg = table && source->offset < table->length() ? &table->registers[source->offset] : nullptr;
    analog_conversions_[n] = tenths_conversion(reg, mapping_.analog_raw[n]);
  }
  publish_mapped_bits();
}

std::uint16_t RegisterStore::read_source(const SourceRef& source) const {
  if (!source.bit) return read(source.bank, source.offset);
  if (!measured(source.bank, source.offset)) return 0;
  return (read(source.bank, source.offset) >> *source.bit) & 1u;
}

std::uint16_t RegisterStore::mapped_bits(const std::array<std::optional<SourceRef>, Mapping::entries>& sources) const {
  std::uint16_t bits = 0;
  for (std::size_t n = 0; n < sources.size(); ++n)
    if (sources[n] && read_source(*sources[n])) bits |= static_cast<std::uint16_t>(1u << n);
  return bits;
}

std::uint16_t RegisterStore::read(BankId bank, std::uint16_t offset) const {
  std::uint16_t value = 0;
  read(bank, offset, std::span(&value, 1));
  return value;
}

bool RegisterStore::store_telegram(BankId id, std::uint16_t offset, std::span<const std::uint16_t> values) {
  auto& bank = bank_(id);
  if (std::size_t{offset} + values.size() > bank.filled_length) return false;
  std::copy(values.begin(), values.end(), bank.raw.begin() + offset);
  std::fill_n(bank.carried.begin() + offset, values.size(), std::uint8_t{1});
  refresh_served(bank, offset, values.size());
  publish_mapped_bits();
  content_changed();
  return true;
}

void RegisterStore::set_online(BankId id, bool online) {
  auto& bank = bank_(id);
  if (bank.online == online) return;
  bank.online = online;
  refresh_served(bank, 0, bank.length);
  publish_mapped_bits();
  content_changed();
}

void RegisterStore::write(BankId id, std::uint16_t offset, std::uint16_t value) {
  bank_(id).raw[offset] = value;
  bank_(id).carried[offset] = 1;
  notify(id, offset, value);
  publish_mapped_bits();
  content_changed();
}

void RegisterStore::publish_mapped_bits() {
  const auto inputs = mapped_bits(mapping_.user_inputs);
  const auto outputs = mapped_bits(mapping_.user_outputs);
  if (inputs != published_user_inputs_) {
    published_user_inputs_ = inputs;
    notify(BankId::C, c_bank::user_binary_inputs, inputs);
  }
  if (outputs != published_user_outputs_) {
    published_user_outputs_ = outputs;
    notify(BankId::C, c_bank::user_binary_outputs, outputs);
  }
}

void RegisterStore::set_user_output(unsigned n, std::uint16_t value) {
  const auto offset = static_cast<std::uint16_t>(c_bank::user_analog_outputs + n - 1);
  bank_(BankId::C).raw[offset] = value;
  notify(BankId::C, offset, value);
  content_changed();
}

void RegisterStore::set_modbus_error(bool error) {
  if (std::exchange(modbus_error_, error) != error) content_changed();
}

std::uint16_t RegisterStore::online_bits() const {
  std::uint16_t bits = 0;
  for (unsigned n = 1; n <= 4; ++n)
    if (bank_(device_bank(n)).online) bits |= static_cast<std::uint16_t>(1u << (n - 1));
  for (unsigned n = 1; n <= 7; ++n)
    if (bank_(module_bank(n)).online) bits |= static_cast<std::uint16_t>(1u << (7 + n));
  if (modbus_error_) bits |= 1u << c_bank::modbus_error_bit;
  return bits;
}

void RegisterStore::take_state_from(const RegisterStore& old) {
  for (BankId id : all_banks) {
    const bool same_shape = shapes_[index_of(id)].table == old.shapes_[index_of(id)].table &&
                            length(id) == old.length(id);
    if (!same_shape) continue;
    if (id == BankId::A || id == BankId::B) continue;  // computed from their sources
    bank_(id) = old.bank_(id);
  }
  modbus_error_ = old.modbus_error_;
  publish_mapped_bits();
}

}  // namespace unima::banks
