// ValueModel's layout: which values each bank of a config has, from the device tables and
// the mapping (SPEC §17). Built once per config.

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "banks/tenths.hpp"
#include "config/config.hpp"
#include "values/value_model.hpp"

namespace unima::values {

namespace {

using banks::BankId;
using banks::RegisterDef;
using banks::RegisterKind;

// The decimals a scale has (0.1 -> 1, 0.78125 -> 5): a reading keeps exactly those, not
// binary noise. The tables' scales have at most 7.
unsigned decimals_of(double scale) {
  unsigned decimals = 0;
  double factor = 1;
  while (decimals < 7 && std::abs(scale * factor - std::round(scale * factor)) > 1e-9 * factor) {
    ++decimals;
    factor *= 10;
  }
  return decimals;
}

ValueDef def(std::string name, std::string label, std::string unit, Decoding decoding, std::vector<std::uint16_t> offsets,
             double scale = 1.0) {
  ValueDef d;
  d.name = std::move(name);
  d.label = std::move(label);
  d.unit = std::move(unit);
  d.decoding = decoding;
  d.offsets = std::move(offsets);
  d.scale = scale;
  d.decimals = decimals_of(scale);
  return d;
}

// Bit `bit` of a word, as a boolean.
ValueDef bit_def(std::string name, std::string label, Decoding decoding, std::uint16_t offset, std::uint8_t bit) {
  auto d = def(std::move(name), std::move(label), "", decoding, {offset});
  d.type = ValueType::boolean;
  d.first_bit = d.last_bit = bit;
  return d;
}

void add_bit_word(std::vector<ValueDef>& values, const RegisterDef& reg) {
  values.push_back(def(reg.id, reg.label, "", Decoding::word, {reg.offset}));
  for (const auto& field : reg.fields) {
    auto bits = def(banks::field_value_name(reg, field), field.label, "", Decoding::bit_field, {reg.offset});
    bits.first_bit = field.first_bit;
    bits.last_bit = field.last_bit;
    if (field.first_bit == field.last_bit) bits.type = ValueType::boolean;
    values.push_back(std::move(bits));
  }
}

void add_byte_pair(std::vector<ValueDef>& values, const RegisterDef& reg) {
  std::vector<banks::Field> fields = reg.fields;
  if (fields.empty()) {  // no table has one without fields; the bytes by position then
    fields.push_back({0, 7, reg.id + "_low", reg.label, "", reg.unit, reg.scale, ""});
    fields.push_back({8, 15, reg.id + "_high", reg.label, "", reg.unit, reg.scale, ""});
  }
  for (const auto& field : fields) {
    auto byte = def(banks::field_value_name(reg, field), field.label, field.unit, Decoding::byte_field, {reg.offset}, field.scale);
    byte.first_bit = field.first_bit;
    byte.last_bit = field.last_bit;
    values.push_back(std::move(byte));
  }
}

void add_ascii_pair(std::vector<ValueDef>& values, const RegisterDef& reg) {
  auto text = def(reg.id, reg.label, "", Decoding::ascii, {reg.offset});
  text.type = ValueType::text;
  // The first character is the byte the table names first (NSU2: the low byte).
  text.first_bit = reg.fields.empty() ? 0 : reg.fields.front().first_bit;
  values.push_back(std::move(text));
}

std::vector<ValueDef> table_values(const banks::DeviceTable& table, std::uint16_t length) {
  std::vector<ValueDef> values;
  for (const auto& reg : table.registers) {
    if (reg.offset >= length) break;
    switch (reg.kind) {
      case RegisterKind::analog: {
        auto analog = def(reg.id, reg.label, reg.unit, Decoding::analog, {reg.offset}, reg.scale);
        analog.is_signed = reg.is_signed;
        values.push_back(std::move(analog));
        break;
      }
      case RegisterKind::u32_low:
        // The parser checked that the u32_high of the same pair follows.
        if (reg.offset + 1 < length)
          values.push_back(def(reg.pair, banks::pair_label(reg.label), reg.unit, Decoding::pair32,
                               {reg.offset, static_cast<std::uint16_t>(reg.offset + 1)}, reg.scale));
        break;
      case RegisterKind::bits: add_bit_word(values, reg); break;
      case RegisterKind::byte_pair: add_byte_pair(values, reg); break;
      case RegisterKind::ascii_pair: add_ascii_pair(values, reg); break;
      case RegisterKind::u32_high:  // one value with its u32_low
      case RegisterKind::reserve: break;
    }
  }
  return values;
}

const RegisterDef* source_register(const banks::BankShapes& shapes, const banks::SourceRef& source) {
  const auto* table = shapes[index_of(source.bank)].table;
  return table && source.offset < table->length() ? &table->registers[source.offset] : nullptr;
}

// Bank A holds an analog source in tenths of its unit (banks/tenths.hpp), anything else
// as the source reads: either way the value is in the source's unit.
std::vector<ValueDef> a_values(const banks::BankShapes& shapes, const banks::Mapping& mapping) {
  std::vector<ValueDef> values;
  for (std::uint16_t n = 0; n < banks::analog_bank_length; ++n) {
    const auto& source = mapping.analog[n];
    if (!source) {
      values.push_back(def(fmt::format("a_{:02x}", n), "", "", Decoding::mapped, {n}, 0.1));
      continue;
    }
    const auto* reg = source_register(shapes, *source);
    const auto conversion = banks::tenths_conversion(reg, mapping.analog_raw[n]);
    const bool in_tenths = !conversion.copy || !reg;  // W, the only source without a table, holds tenths
    auto entry = def(source->text, reg ? reg->label : "", reg ? reg->unit : "", Decoding::mapped, {n},
                     in_tenths ? 0.1 : reg->scale);
    entry.is_signed = in_tenths || (reg->kind == RegisterKind::analog && reg->is_signed);
    entry.source = source;
    values.push_back(std::move(entry));
  }
  return values;
}

std::vector<ValueDef> b_values(const banks::Mapping& mapping) {
  std::vector<ValueDef> values;
  for (std::uint8_t bit = 0; bit < banks::Mapping::entries; ++bit) {
    const auto& source = mapping.bits[bit];
    if (!source) continue;
    auto entry = bit_def(source->text, "", Decoding::mapped_bit, 0, bit);
    entry.source = source;
    values.push_back(std::move(entry));
  }
  if (values.empty()) {  // the page says so; MQTT leaves it out
    auto none = def("b", "", "", Decoding::mapped_bit, {0});
    none.type = ValueType::boolean;
    values.push_back(std::move(none));
  }
  return values;
}

// C+0x10 and C+0x12 show mapped bits as B does (SPEC §1): an unmapped bit is not mapped
// rather than false, a mapped one says why its source has no value.
void map_user_bits(std::vector<ValueDef>& values, std::uint16_t offset,
                   const std::array<std::optional<banks::SourceRef>, banks::Mapping::entries>& sources) {
  for (auto& value : values)
    if (value.decoding == Decoding::bit_field && value.offsets.front() == offset && value.first_bit == value.last_bit) {
      value.decoding = Decoding::mapped_bit;
      value.source = sources[value.first_bit];
    }
}

std::vector<ValueDef> w_values() {
  std::vector<ValueDef> values;
  for (std::uint16_t n = 0; n < banks::analog_bank_length; ++n) {
    auto entry = def(fmt::format("w_{:02x}", n), "", "", Decoding::analog, {n}, 0.1);
    entry.is_signed = true;  // tenths, which a master may write below zero (SPEC §12: -32768..65535)
    values.push_back(std::move(entry));
  }
  return values;
}

// X is a bit word without a table (SPEC §17): the word, and each of its sixteen bits as
// a boolean named by its number, as a table's bit word names its fields.
std::vector<ValueDef> x_values() {
  std::vector<ValueDef> values{def("x", "", "", Decoding::word, {0})};
  for (std::uint8_t bit = 0; bit < 16; ++bit) values.push_back(bit_def(fmt::format("x.{}", bit), "", Decoding::bit_field, 0, bit));
  return values;
}

}  // namespace

unsigned display_decimals(const ValueDef& def) {
  unsigned decimals = 0;
  // The tolerance keeps 0.1 × 10 (0.99999… in binary at worst) at one decimal.
  for (double step = def.scale; decimals < def.decimals && step < 1 - 1e-9; step *= 10) ++decimals;
  return decimals;
}

ValueModel::ValueModel(const config::Config& config) {
  const auto shapes = config::bank_shapes(config);
  for (const BankId bank : banks::all_banks) {
    const auto& shape = shapes[index_of(bank)];
    if (shape.length == 0) continue;
    BankValues layout{bank, {}};
    switch (bank) {
      case BankId::A: layout.values = a_values(shapes, config.mapping); break;
      case BankId::B: layout.values = b_values(config.mapping); break;
      case BankId::W: layout.values = w_values(); break;
      case BankId::X: layout.values = x_values(); break;
      default:
        if (shape.table) layout.values = table_values(*shape.table, shape.length);
    }
    if (bank == BankId::C) {
      map_user_bits(layout.values, banks::c_bank::user_binary_inputs, config.mapping.user_inputs);
      map_user_bits(layout.values, banks::c_bank::user_binary_outputs, config.mapping.user_outputs);
    }
    if (!layout.values.empty()) banks_.push_back(std::move(layout));
  }
}

const BankValues* ValueModel::bank(BankId bank) const {
  const auto found = std::find_if(banks_.begin(), banks_.end(), [&](const BankValues& b) { return b.bank == bank; });
  return found == banks_.end() ? nullptr : &*found;
}

}  // namespace unima::values
