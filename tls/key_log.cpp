#include "tls/key_log.hpp"

#include <openssl/crypto.h>

namespace unima::tls {

namespace {

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

bool read_key_log_secret(std::string_view line, std::string_view label, std::vector<std::uint8_t>& secret) {
  if (!line.starts_with(label) || line.size() <= label.size() || line[label.size()] != ' ') return false;
  const auto hex = line.substr(line.rfind(' ') + 1);
  secret.clear();
  secret.reserve(hex.size() / 2);
  for (std::size_t i = 0; i + 1 < hex.size(); i += 2) {
    const int high = hex_digit(hex[i]);
    const int low = hex_digit(hex[i + 1]);
    if (high < 0 || low < 0) {
      OPENSSL_cleanse(secret.data(), secret.size());
      secret.clear();
      return false;
    }
    secret.push_back(static_cast<std::uint8_t>(high << 4 | low));
  }
  return true;
}

}  // namespace unima::tls
