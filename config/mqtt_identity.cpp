#include "config/mqtt_identity.hpp"

#include <algorithm>
#include <cctype>

namespace unima::config {

namespace {

constexpr std::size_t longest_client_id = 64;

}  // namespace

std::string machine_id_digits(std::string_view text) {
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.remove_suffix(1);
  if (text.size() != 32 || !std::all_of(text.begin(), text.end(), [](char c) { return std::isxdigit(static_cast<unsigned char>(c)); }))
    return {};
  std::string digits(text.substr(0, 8));
  std::transform(digits.begin(), digits.end(), digits.begin(), [](char c) { return static_cast<char>(std::tolower(c)); });
  return digits;
}

std::string default_client_id(std::string_view host_name, std::string_view machine_id_digits) {
  std::string id = "unima-bridge";
  if (host_name.empty()) return machine_id_digits.empty() ? id : id + "-" + std::string(machine_id_digits);
  const auto suffix = machine_id_digits.empty() ? std::string() : "-" + std::string(machine_id_digits);
  const auto room = longest_client_id - id.size() - 1 - suffix.size();
  return id + "-" + std::string(host_name.substr(0, room)) + suffix;
}

}  // namespace unima::config
