#pragma once
// How the project's files and command lines write a number (a register, an address, a
// value): decimal, or hex after 0x as the seed writes registers ("0x0200"). One reader
// for the config, the device tables and profiles, source references and the monitor's
// filter.

#include <charconv>
#include <optional>
#include <string_view>

namespace unima::banks {

/// The number `text` holds, whole; nullopt when it is not one.
inline std::optional<unsigned long> parse_number(std::string_view text) {
  const bool hex = text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X');
  if (hex) text.remove_prefix(2);
  unsigned long value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value, hex ? 16 : 10);
  if (text.empty() || ec != std::errc{} || end != text.data() + text.size()) return std::nullopt;
  return value;
}

}  // namespace unima::banks
