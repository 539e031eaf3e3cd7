#include "mqtt/config_set.hpp"

namespace unima::mqtt {

bool takes_configs(const config::Config& config) {
  return config.mqtt && config.remote_config && config.remote_config->mqtt;
}

std::string config_set_topic(std::string_view prefix) { return std::string(prefix) + "/config/set"; }

std::string config_result_topic(std::string_view prefix) { return std::string(prefix) + "/config/result"; }

ConfigMessage judge_config_message(std::string_view payload, bool retained) {
  // Empty first: clearing a retained config publishes an empty retained message, which the
  // broker also hands to every subscriber, the bridge included, as a plain message.
  if (payload.empty()) return ConfigMessage::clearing;
  return retained ? ConfigMessage::retained : ConfigMessage::config;
}

std::string config_author(const std::vector<std::pair<std::string, std::string>>& user_properties) {
  std::string author;
  for (const auto& [name, value] : user_properties) {
    if (name != author_property) continue;
    author = value;
    break;
  }
  if (author.size() > max_author_bytes) {
    auto end = max_author_bytes;
    // Back to a character's first byte: no half of a UTF-8 sequence at the end.
    while (end > 0 && (static_cast<unsigned char>(author[end]) & 0xC0) == 0x80) --end;
    author.resize(end);
  }
  for (auto& c : author)
    if (const auto byte = static_cast<unsigned char>(c); byte < 0x20 || byte == 0x7F) c = '?';
  return author.empty() ? std::string("mqtt") : author;
}

}  // namespace unima::mqtt
