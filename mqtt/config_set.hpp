#pragma once
// Configs from afar over MQTT (SPEC §19): with `remote_config.mqtt: true` the bridge takes
// the whole YAML text of a config on `<prefix>/config/set` and answers on
// `<prefix>/config/result` (or an allowed MQTT 5 Response Topic). What a message there is
// — a config to hand to the one flow, the clearing of a retained message, or a retained
// one to drop — and who sent it. Pure: io/mqtt/mqtt_service publishes and subscribes.

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "config/config.hpp"

namespace unima::mqtt {

/// Whether the config `config` takes configs on `<prefix>/config/set`.
bool takes_configs(const config::Config& config);

/// `<prefix>/config/set`: a topic, not a filter, so it never overlaps `<prefix>/set/#`
/// nor takes the bridge's own `<prefix>/config/result`.
std::string config_set_topic(std::string_view prefix);
std::string config_result_topic(std::string_view prefix);

enum class ConfigMessage {
  config,    // a config: to the flow
  clearing,  // an empty message: how a retained one is cleared (the bridge's own, or anyone's)
  retained,  // from the broker's store: never applied (it would come again at every connection); cleared
};

ConfigMessage judge_config_message(std::string_view payload, bool retained);

/// The MQTT 5 user property naming the sender of a config.
inline constexpr std::string_view author_property = "by";
/// An author is a name in a log line and the history, not a document.
inline constexpr std::size_t max_author_bytes = 64;

/// The author of a config: the user property `by` (the first one), its control characters
/// as '?' and cut at max_author_bytes on a UTF-8 character's start; without one, or empty,
/// "mqtt".
std::string config_author(const std::vector<std::pair<std::string, std::string>>& user_properties);

}  // namespace unima::mqtt
