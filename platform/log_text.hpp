#pragma once
// Text that came from outside (a feed line, a peer's bytes, a certificate's role, an MQTT
// topic or payload) goes into the log and the monitor escaped, so that it can never forge
// a line or a terminal sequence: control characters become \n, \r, \t or \xNN; everything
// else is left as it is. log_safe is that for a log call's argument; the monitor's line
// writer and the log's formatter use the same escape byte by byte (escape_byte).

#include <cstddef>
#include <string>
#include <string_view>

namespace unima::platform {

/// Bytes that must not reach a log or monitor line as they are: C0 controls and DEL.
constexpr bool is_control(unsigned char byte) { return byte < 0x20 || byte == 0x7F; }

/// The longest escape escape_byte writes ("\xNN").
inline constexpr std::size_t max_escape = 4;

/// Writes the escape of `byte` — \n, \r, \t, else \xNN — at `out`; returns its end.
inline char* escape_byte(char* out, unsigned char byte) {
  static constexpr char hex[] = "0123456789ABCDEF";
  *out++ = '\\';
  switch (byte) {
    case '\n': *out++ = 'n'; break;
    case '\r': *out++ = 'r'; break;
    case '\t': *out++ = 't'; break;
    default:
      *out++ = 'x';
      *out++ = hex[byte >> 4];
      *out++ = hex[byte & 0xF];
  }
  return out;
}

inline std::string log_safe(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (!is_control(byte)) {
      out += c;
      continue;
    }
    char escape[max_escape];
    out.append(escape, escape_byte(escape, byte));
  }
  return out;
}

}  // namespace unima::platform
