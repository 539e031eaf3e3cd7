#include "monitor/command_filter.hpp"

#include <algorithm>

#include "banks/number_text.hpp"
#include "modbus/protocol.hpp"
#include "modbus/bytes.hpp"

namespace unima::monitor {

namespace {

RegisterRange range_of(std::uint16_t start, std::uint16_t count) {
  const std::uint32_t last = std::uint32_t{start} + (count == 0 ? 0 : count - 1u);
  return {start, static_cast<std::uint16_t>(std::min<std::uint32_t>(last, 0xFFFF))};
}

bool overlaps(RegisterRange a, std::uint16_t from, std::uint16_t to) { return a.first <= to && a.last >= from; }

std::string hex4(std::uint16_t value) {
  static constexpr char digits[] = "0123456789ABCDEF";
  std::string s = "0x0000";
  for (int i = 0; i < 4; ++i) s[5 - i] = digits[(value >> (4 * i)) & 0xF];
  return s;
}


}  // namespace

TouchedRanges touched_ranges(std::span<const std::uint8_t> pdu) {
  TouchedRanges touched;
  if (pdu.empty()) return touched;
  const auto add = [&](RegisterRange range) { touched.ranges[touched.count++] = range; };
  switch (pdu[0]) {
    case modbus::function::read_coils:
    case modbus::function::read_discrete_inputs:
    case modbus::function::read_holding_registers:
    case modbus::function::read_input_registers:
    case modbus::function::write_multiple_coils:
    case modbus::function::write_multiple_registers:
      if (pdu.size() >= 5) add(range_of(modbus::be16(pdu, 1), modbus::be16(pdu, 3)));
      break;
    case modbus::function::write_single_coil:
    case modbus::function::write_single_register:
      if (pdu.size() >= 3) add(range_of(modbus::be16(pdu, 1), 1));
      break;
    case 0x17:  // read/write multiple registers: read start, count, write start, count
      if (pdu.size() >= 5) add(range_of(modbus::be16(pdu, 1), modbus::be16(pdu, 3)));
      if (pdu.size() >= 9) add(range_of(modbus::be16(pdu, 5), modbus::be16(pdu, 7)));
      break;
    default: break;
  }
  return touched;
}

bool CommandFilter::matches(std::optional<std::uint8_t> query_address, std::span<const std::uint8_t> pdu) const {
  if (address && query_address != address) return false;
  if (function && (pdu.empty() || pdu[0] != *function)) return false;
  if (!filters_registers()) return true;
  const auto touched = touched_ranges(pdu);
  for (std::uint8_t i = 0; i < touched.count; ++i)
    if (overlaps(touched.ranges[i], from, to)) return true;
  return false;
}

std::string CommandFilter::describe() const {
  std::string s = "ad=";
  s += address ? std::to_string(*address) : "xx";
  s += " fn=";
  s += function ? std::to_string(*function) : "xx";
  s += " from=" + hex4(from) + " to=" + hex4(to);
  return s;
}

void set_filter_field(CommandFilter& filter, FilterField field, std::string_view text) {
  std::optional<unsigned long> value;  // nullopt: xx, any
  if (text != "xx" && text != "XX") {
    const unsigned long max = field == FilterField::address || field == FilterField::function ? 0xFF : 0xFFFF;
    value = banks::parse_number(text);
    if (!value || *value > max)
      throw FilterSyntaxError("'" + std::string(text) + "' is not xx or a number 0.." + std::to_string(max));
  }
  const auto byte = [&] { return value ? std::optional(static_cast<std::uint8_t>(*value)) : std::nullopt; };
  switch (field) {
    case FilterField::address: filter.address = byte(); break;
    case FilterField::function: filter.function = byte(); break;
    // Either end of the range at "any" is that end of the whole space.
    case FilterField::from: filter.from = static_cast<std::uint16_t>(value.value_or(0x0000)); break;
    case FilterField::to: filter.to = static_cast<std::uint16_t>(value.value_or(0xFFFF)); break;
  }
}

void check_filter_range(const CommandFilter& filter) {
  if (filter.from > filter.to) throw FilterSyntaxError("from=" + hex4(filter.from) + " is after to=" + hex4(filter.to));
}

CommandFilter parse_command_filter(std::string_view expression) {
  struct Key {
    std::string_view name;
    FilterField field;
  };
  static constexpr Key keys[] = {{"ad", FilterField::address}, {"fn", FilterField::function},
                                 {"from", FilterField::from}, {"to", FilterField::to}};
  CommandFilter filter;
  bool seen[std::size(keys)] = {};
  std::size_t at = 0;
  while (at < expression.size()) {
    if (expression[at] == ' ' || expression[at] == '\t' || expression[at] == ',') {
      ++at;
      continue;
    }
    auto end = expression.find_first_of(" \t,", at);
    if (end == std::string_view::npos) end = expression.size();
    const auto term = expression.substr(at, end - at);
    at = end;
    const auto equals = term.find('=');
    if (equals == std::string_view::npos)
      throw FilterSyntaxError("filter: '" + std::string(term) + "' is not key=value (keys: ad, fn, from, to)");
    const auto name = term.substr(0, equals);
    const auto key = std::find_if(std::begin(keys), std::end(keys), [&](const Key& k) { return k.name == name; });
    if (key == std::end(keys))
      throw FilterSyntaxError("filter: unknown key '" + std::string(name) + "' (keys: ad, fn, from, to)");
    auto& seen_key = seen[key - std::begin(keys)];
    if (seen_key) throw FilterSyntaxError("filter: '" + std::string(name) + "' is given twice");
    seen_key = true;
    try {
      set_filter_field(filter, key->field, term.substr(equals + 1));
    } catch (const FilterSyntaxError& e) {
      throw FilterSyntaxError("filter: " + std::string(name) + "=" + e.what());
    }
  }
  try {
    check_filter_range(filter);
  } catch (const FilterSyntaxError& e) {
    throw FilterSyntaxError(std::string("filter: ") + e.what());
  }
  return filter;
}

}  // namespace unima::monitor
