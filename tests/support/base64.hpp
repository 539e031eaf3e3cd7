#pragma once
// RFC 4648 base64 with padding, the client's side of HTTP basic authentication in tests
// (the daemon only decodes: web::decode_base64).

#include <cstdint>
#include <string>

namespace unima::test_support {

inline std::string base64(const std::string& text) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < text.size(); i += 3) {
    const std::uint32_t n = static_cast<std::uint8_t>(text[i]) << 16 |
                            (i + 1 < text.size() ? static_cast<std::uint8_t>(text[i + 1]) << 8 : 0) |
                            (i + 2 < text.size() ? static_cast<std::uint8_t>(text[i + 2]) : 0);
    out += alphabet[n >> 18 & 63];
    out += alphabet[n >> 12 & 63];
    out += i + 1 < text.size() ? alphabet[n >> 6 & 63] : '=';
    out += i + 2 < text.size() ? alphabet[n & 63] : '=';
  }
  return out;
}

}  // namespace unima::test_support
