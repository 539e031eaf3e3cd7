#include "config/yaml_reader.hpp"

#include <algorithm>

#include <charconv>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "banks/number_text.hpp"
#include "modbus/plc_numbers.hpp"

namespace unima::config {

std::string YamlReader::position(const YAML::Node& node) const {
  const auto mark = node.Mark();
  if (mark.is_null()) return origin_;
  return fmt::format("{}:{}:{}", origin_, mark.line + 1, mark.column + 1);
}

void YamlReader::fail(const YAML::Node& node, std::string_view message) const {
  throw ConfigError(fmt::format("{}: {}", position(node), message));
}

void YamlReader::warn(const YAML::Node& node, std::string_view message) const {
  warnings_.push_back(warning_text(position(node), message));
}

void YamlReader::expect_keys(const YAML::Node& map, std::string_view what,
                             std::initializer_list<std::string_view> allowed) const {
  expect_keys(map, what, std::span(allowed.begin(), allowed.size()));
}

void YamlReader::expect_keys(const YAML::Node& map, std::string_view what, std::span<const std::string_view> allowed) const {
  if (map.IsNull()) return;
  // "address 5" where "address: 5" was meant, read as a key of a null value or as the
  // section's whole value: a ':' left out (issue 44).
  const auto colon_left_out = [&](const YAML::Node& node) {
    const auto& text = node.Scalar();
    const auto space = text.find(' ');
    const auto first_word = std::string_view(text).substr(0, space);
    if (space == std::string::npos || std::find(allowed.begin(), allowed.end(), first_word) == allowed.end()) return;
    fail(node, fmt::format("'{}' has no ':' after its key: write '{}: {}'", text, first_word, text.substr(space + 1)));
  };
  if (!map.IsMap()) {
    if (map.IsScalar()) colon_left_out(map);
    fail(map, fmt::format("{} must be a mapping of keys", what));
  }
  for (const auto& entry : map) {
    const auto key = entry.first.Scalar();
    bool known = false;
    for (auto a : allowed) known = known || a == key;
    if (known) continue;
    if (entry.second.IsNull()) colon_left_out(entry.first);
    fail(entry.first, fmt::format("unknown key '{}' in {} (known: {})", key, what, fmt::join(allowed, ", ")));
  }
}

double YamlReader::decimal(const YAML::Node& node) const {
  const auto text = this->text(node);
  try {
    std::size_t used = 0;
    const double value = std::stod(text, &used);
    if (used == text.size() && std::isfinite(value)) return value;
  } catch (const std::exception&) {
  }
  fail(node, fmt::format("'{}' is not a number", text));
}

unsigned long YamlReader::number(const YAML::Node& node, unsigned long min, unsigned long max) const {
  if (!node.IsScalar()) fail(node, "expected a number");
  const auto& s = node.Scalar();
  const auto parsed = banks::parse_number(s);
  if (!parsed) fail(node, fmt::format("'{}' is not a number (write decimal or 0x hex)", s));
  const auto value = *parsed;
  const bool hex = s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X');
  if (value < min || value > max) {
    if (hex || max > 255) fail(node, fmt::format("{} is out of range 0x{:X}..0x{:X} ({}..{})", s, min, max, min, max));
    fail(node, fmt::format("{} is out of range {}..{}", s, min, max));
  }
  return value;
}

std::uint16_t YamlReader::register_address(const YAML::Node& node) const {
  if (!node.IsScalar()) fail(node, "expected a register address");
  const auto& written = node.Scalar();
  const auto parsed = banks::parse_number(written);
  const bool decimal = parsed && !(written.size() > 2 && written[0] == '0' && (written[1] == 'x' || written[1] == 'X'));
  const auto plc = decimal ? modbus::read_plc_number(*parsed) : std::nullopt;
  const auto meaning = [&] {
    return fmt::format("if {} register {} (PLC numbering, from 1) was meant, write its address 0x{:04X}",
                       plc->table == modbus::PlcTable::input ? "input" : "holding", written, plc->address);
  };
  if (plc && *parsed > 0xFFFF) fail(node, fmt::format("{} is not a register address (0x0000..0xFFFF); {}", written, meaning()));
  const auto address = static_cast<std::uint16_t>(number(node, 0, 0xFFFF));
  if (plc)
    warn(node, fmt::format("register {} is taken as address 0x{:04X}; {}; write 0x{:04X} to keep this address without "
                           "this warning",
                           written, address, meaning(), address));
  return address;
}

bool YamlReader::boolean(const YAML::Node& node) const {
  const auto s = text(node);
  if (s == "true" || s == "yes" || s == "on") return true;
  if (s == "false" || s == "no" || s == "off") return false;
  fail(node, fmt::format("'{}' is not a boolean (true or false)", s));
}

std::string YamlReader::text(const YAML::Node& node) const {
  if (!node.IsScalar()) fail(node, "expected a single value");
  return node.Scalar();
}

namespace {

std::optional<std::chrono::microseconds> parse_duration(std::string_view s) {
  std::size_t digits = 0;
  while (digits < s.size() && s[digits] >= '0' && s[digits] <= '9') ++digits;
  const std::string_view unit = s.substr(digits);
  unsigned long long value = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + digits, value);
  if (digits == 0 || ec != std::errc{} || end != s.data() + digits || value >= 1'000'000'000ULL) return std::nullopt;
  using std::chrono::microseconds;
  if (unit == "us" || unit == "µs") return microseconds(value);
  if (unit == "ms") return microseconds(value * 1000);
  if (unit == "s") return microseconds(value * 1'000'000);
  if (unit == "m" || unit == "min") return microseconds(value * 60'000'000);
  if (unit == "h") return microseconds(value * 3'600'000'000ULL);
  return std::nullopt;
}

}  // namespace

Duration YamlReader::duration(const YAML::Node& node) const {
  const auto s = text(node);
  const auto parsed = parse_duration(s);
  if (parsed && *parsed % Duration(1) == std::chrono::microseconds(0)) return std::chrono::duration_cast<Duration>(*parsed);
  fail(node, fmt::format("'{}' is not a duration (write e.g. 200ms, 1s, 5m)", s));
}

std::chrono::microseconds YamlReader::fine_duration(const YAML::Node& node) const {
  const auto s = text(node);
  if (const auto parsed = parse_duration(s)) return *parsed;
  fail(node, fmt::format("'{}' is not a duration (write e.g. 1750us, 2ms)", s));
}

std::uint64_t YamlReader::byte_size(const YAML::Node& node, std::uint64_t min, std::uint64_t max) const {
  const auto s = text(node);
  std::size_t digits = 0;
  while (digits < s.size() && s[digits] >= '0' && s[digits] <= '9') ++digits;
  const std::string_view unit = std::string_view(s).substr(digits);
  std::uint64_t value = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + digits, value);
  unsigned shift = 64;
  if (unit.empty() || unit == "B") shift = 0;
  else if (unit == "k" || unit == "K" || unit == "kB" || unit == "KB" || unit == "KiB") shift = 10;
  else if (unit == "M" || unit == "MB" || unit == "MiB") shift = 20;
  else if (unit == "G" || unit == "GB" || unit == "GiB") shift = 30;
  if (digits == 0 || ec != std::errc{} || end != s.data() + digits || shift == 64)
    fail(node, fmt::format("'{}' is not a size (write e.g. 65536, 64k, 10MB)", s));
  if (value > (max >> shift) || (value << shift) < min)
    fail(node, fmt::format("{} is out of range {}..{} bytes", s, min, max));
  value <<= shift;
  return value;
}

std::string YamlReader::choice(const YAML::Node& node, std::initializer_list<std::string_view> choices) const {
  const auto s = text(node);
  for (auto c : choices)
    if (c == s) return s;
  fail(node, fmt::format("'{}' is not one of: {}", s, fmt::join(choices, ", ")));
}

}  // namespace unima::config
