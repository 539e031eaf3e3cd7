#pragma once
// A JSON text that came from outside — a feed line, a recording's line, a monitor log line
// read back — is one value and nothing after it but white space (RFC 8259). nlohmann's
// lexer alone lets one thing through: it takes a NUL byte for the end of its input (the
// end of a C string), so `{…}\0garbage` would read as `{…}`. JSON has no place for a raw
// NUL, not even inside a string, so a text holding one is not JSON wherever the NUL is.

#include <string>
#include <string_view>
#include <variant>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace unima::platform {

/// The value `text` holds, or why it is not JSON ("not JSON: …"). Never throws.
inline std::variant<nlohmann::json, std::string> parse_json_text(std::string_view text) {
  if (const auto nul = text.find('\0'); nul != std::string_view::npos)
    return fmt::format("not JSON: a NUL byte at byte {}", nul + 1);
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // parse errors, and numbers past a double
    return fmt::format("not JSON: {}", e.what());
  }
}

}  // namespace unima::platform
