// ValueModel::evaluate: a bank's raw registers read as its values (SPEC §17).

#include <cmath>

#include "values/value_model.hpp"

namespace unima::values {

namespace {

using banks::BankId;
using Register = std::optional<std::uint16_t>;

constexpr std::uint8_t byte_not_measured = 255;

Value null(State state) { return Value{std::monostate{}, state}; }

double rounded(double value, unsigned decimals) {
  const double factor = std::pow(10.0, decimals);
  return std::round(value * factor) / factor;
}

Value number(const ValueDef& def, double raw) { return Value{rounded(raw * def.scale, def.decimals), State::ok}; }

bool is_station(BankId bank) { return banks::is_device_bank(bank) || banks::is_module_bank(bank); }

Register register_of(const BankReading& reading, std::uint16_t offset) {
  return offset < reading.registers.size() ? reading.registers[offset] : std::nullopt;
}

// A register nobody put a value in: a setpoint no master wrote, or a quantity no telegram carried.
State unset_state(BankId bank) { return banks::is_write_bank(bank) ? State::not_set : State::not_measured; }

// Why a mapped entry has no value: what its source lacks.
State source_state(const banks::SourceRef& source, const Snapshot& snapshot) {
  const auto& reading = snapshot[index_of(source.bank)];
  if (is_station(source.bank) && !reading.online) return State::offline;
  if (!register_of(reading, source.offset)) return unset_state(source.bank);
  return State::not_measured;
}

std::uint16_t bits_of(std::uint16_t raw, const ValueDef& def) {
  const unsigned width = def.last_bit - def.first_bit + 1u;
  return static_cast<std::uint16_t>((raw >> def.first_bit) & ((1u << width) - 1u));
}

char printable(std::uint16_t byte) { return byte >= 0x20 && byte < 0x7F ? static_cast<char>(byte) : '?'; }

Value decoded(const ValueDef& def, const BankReading& reading, BankId bank, const Snapshot& snapshot) {
  const Register raw = register_of(reading, def.offsets.front());
  switch (def.decoding) {
    case Decoding::mapped: {
      if (!def.source) return null(State::not_mapped);
      if (!raw || *raw == banks::not_measured) return null(source_state(*def.source, snapshot));
      return read_word(def, *raw);
    }
    case Decoding::mapped_bit: {
      if (!def.source) return null(State::not_mapped);
      // B reads 0 for a source that has no value; the value says why instead.
      const auto& source = snapshot[index_of(def.source->bank)];
      if ((is_station(def.source->bank) && !source.online) || !register_of(source, def.source->offset))
        return null(source_state(*def.source, snapshot));
      if (!raw) return null(State::not_measured);
      return read_word(def, *raw);
    }
    default: break;
  }
  if (!raw) return null(unset_state(bank));
  if (def.decoding == Decoding::pair32) {
    const Register high = register_of(reading, def.offsets.back());
    if (!high || *raw == banks::not_measured || *high == banks::not_measured) return null(State::not_measured);
    return number(def, static_cast<double>(std::uint32_t{*high} << 16 | *raw));
  }
  return read_word(def, *raw);
}

}  // namespace

Value read_word(const ValueDef& def, std::uint16_t raw) {
  switch (def.decoding) {
    case Decoding::analog:
    case Decoding::mapped:
      if (raw == banks::not_measured) return null(State::not_measured);
      return number(def, def.is_signed ? static_cast<std::int16_t>(raw) : raw);
    case Decoding::byte_field: {
      const auto byte = bits_of(raw, def);
      if (byte == byte_not_measured) return null(State::not_measured);
      return number(def, byte);
    }
    case Decoding::word: return Value{static_cast<double>(raw), State::ok};
    case Decoding::bit_field:
    case Decoding::mapped_bit:
      if (def.type == ValueType::boolean) return Value{bits_of(raw, def) != 0, State::ok};
      return Value{static_cast<double>(bits_of(raw, def)), State::ok};
    case Decoding::ascii: {
      const auto low = printable(raw & 0xFFu), high = printable(raw >> 8);
      return Value{def.first_bit == 0 ? std::string{low, high} : std::string{high, low}, State::ok};
    }
    case Decoding::pair32: break;  // two words: decoded()
  }
  return null(State::not_measured);
}

std::vector<Value> ValueModel::evaluate(BankId bank, const Snapshot& snapshot) const {
  std::vector<Value> values;
  const auto* layout = this->bank(bank);
  if (!layout) return values;
  const auto& reading = snapshot[index_of(bank)];
  // An off-line device has no value at all, not even a bit (SPEC §17).
  const bool offline = is_station(bank) && !reading.online;
  values.reserve(layout->values.size());
  for (const auto& def : layout->values)
    values.push_back(offline ? null(State::offline) : decoded(def, reading, bank, snapshot));
  return values;
}

}  // namespace unima::values
