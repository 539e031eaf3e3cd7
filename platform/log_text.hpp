#pragma once
// Text that came from outside (a feed line, a peer's bytes) goes into the log escaped, so
// that it can never forge a log line or a terminal sequence: control characters become
// \n, \r, \t or \xNN; everything else is left as it is.

#include <string>
#include <string_view>

namespace unima::platform {

inline std::string log_safe(std::string_view text) {
  static constexpr char hex[] = "0123456789ABCDEF";
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '\n') out += "\\n";
    else if (c == '\r') out += "\\r";
    else if (c == '\t') out += "\\t";
    else if (byte < 0x20 || byte == 0x7F) (out += "\\x") += std::string{hex[byte >> 4], hex[byte & 0xF]};
    else out += c;
  }
  return out;
}

}  // namespace unima::platform
