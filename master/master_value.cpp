#include "master/master_value.hpp"

#include <bit>
#include <cmath>
#include <limits>

namespace unima::master {

namespace {

struct TypeName {
  ValueType type;
  std::string_view name;
};
constexpr TypeName type_names[] = {{ValueType::bits, "bits"},   {ValueType::word, "word"},
                                   {ValueType::int16, "int"},   {ValueType::dint, "dint"},
                                   {ValueType::dword, "dword"}, {ValueType::real, "real"}};

std::uint32_t join(WordOrder order, std::span<const std::uint16_t> r) {
  const std::uint32_t first = r[0], second = r[1];
  return order == WordOrder::low_first ? (second << 16 | first) : (first << 16 | second);
}

void split(WordOrder order, std::uint32_t value, std::span<std::uint16_t> r) {
  const auto low = static_cast<std::uint16_t>(value & 0xFFFF), high = static_cast<std::uint16_t>(value >> 16);
  r[0] = order == WordOrder::low_first ? low : high;
  r[1] = order == WordOrder::low_first ? high : low;
}

// Rounds and clamps into [min, max]; NaN goes to 0 (callers that care test it first).
double clamp_rounded(double value, double min, double max) {
  if (std::isnan(value)) return 0;
  const double rounded = std::nearbyint(value);
  return rounded < min ? min : rounded > max ? max : rounded;
}

}  // namespace

std::string_view value_type_name(ValueType type) {
  for (const auto& t : type_names)
    if (t.type == type) return t.name;
  return "?";
}

std::optional<ValueType> parse_value_type(std::string_view name) {
  for (const auto& t : type_names)
    if (t.name == name) return t.type;
  return std::nullopt;
}

std::string_view word_order_name(WordOrder order) { return order == WordOrder::low_first ? "low_first" : "high_first"; }

std::optional<WordOrder> parse_word_order(std::string_view name) {
  if (name == "low_first") return WordOrder::low_first;
  if (name == "high_first") return WordOrder::high_first;
  return std::nullopt;
}

unsigned register_span(ValueType type) {
  switch (type) {
    case ValueType::bits: return 0;
    case ValueType::word:
    case ValueType::int16: return 1;
    default: return 2;
  }
}

bool is_signed(ValueType type) {
  return type == ValueType::int16 || type == ValueType::dint || type == ValueType::real;
}

double decode_value(ValueType type, WordOrder order, std::span<const std::uint16_t> r) {
  switch (type) {
    case ValueType::bits:
    case ValueType::word: return r[0];
    case ValueType::int16: return static_cast<std::int16_t>(r[0]);
    case ValueType::dint: return static_cast<std::int32_t>(join(order, r));
    case ValueType::dword: return join(order, r);
    case ValueType::real: return std::bit_cast<float>(join(order, r));
  }
  return 0;
}

void encode_value(ValueType type, WordOrder order, double value, std::span<std::uint16_t> r) {
  switch (type) {
    case ValueType::bits:
    case ValueType::word: r[0] = static_cast<std::uint16_t>(clamp_rounded(value, 0, 65535)); return;
    case ValueType::int16:
      r[0] = static_cast<std::uint16_t>(static_cast<std::int16_t>(clamp_rounded(value, -32768, 32767)));
      return;
    case ValueType::dint:
      split(order, static_cast<std::uint32_t>(static_cast<std::int32_t>(clamp_rounded(value, -2147483648.0, 2147483647.0))), r);
      return;
    case ValueType::dword: split(order, static_cast<std::uint32_t>(clamp_rounded(value, 0, 4294967295.0)), r); return;
    case ValueType::real: split(order, std::bit_cast<std::uint32_t>(static_cast<float>(value)), r); return;
  }
}

std::uint16_t to_bridge_register(double device_value, double scale, bool signed_result) {
  const double value = device_value * scale;
  if (std::isnan(value)) return not_measured;
  if (signed_result)
    return static_cast<std::uint16_t>(static_cast<std::int16_t>(clamp_rounded(value, -32768, not_measured - 1)));
  return static_cast<std::uint16_t>(clamp_rounded(value, 0, 65535));
}

double from_bridge_register(std::uint16_t raw, bool signed_source, double scale) {
  const double value = signed_source ? static_cast<double>(static_cast<std::int16_t>(raw)) : raw;
  return value / scale;
}

}  // namespace unima::master
