#pragma once
// Where the bridge may answer an MQTT 5 command (SPEC §15). A command's Response Topic is
// chosen by whoever may publish `<prefix>/set/…`, and the bridge publishes its answer with
// its own credentials — which a broker ACL must allow on the bridge's status, birth, bank,
// Sparkplug and discovery topics. So the bridge itself keeps answers to the topics
// `mqtt.response_topics` lists and off every topic it publishes for its own ends; an
// answer refused here goes to `<prefix>/set/result` (SPEC §12). Pure.

#include <cstddef>
#include <string_view>

#include "config/config.hpp"

namespace unima::mqtt {

enum class ResponseTopicVerdict {
  answer_there,
  not_a_topic,   // empty, longer than max_response_topic_bytes, a NUL, or a wildcard
  bridge_topic,  // the bridge's own: its prefix outside reply/, spBv1.0/…, the discovery prefix, $…
  not_listed,    // matches none of mqtt.response_topics
};

/// Longer Response Topics are refused: an answer's topic is a short name an application
/// subscribes to, and the bridge does not publish megabytes of topic for anyone.
inline constexpr std::size_t max_response_topic_bytes = 256;

/// Whether a command's answer may go to `topic` under `mqtt` (its prefix, its
/// response_topics, its discovery prefix).
ResponseTopicVerdict judge_response_topic(std::string_view topic, const config::MqttConfig& mqtt);

/// Why, for the log: "…" completes "the Response Topic is …".
std::string_view verdict_text(ResponseTopicVerdict verdict);

}  // namespace unima::mqtt
