#include "mqtt/response_topic.hpp"

#include <algorithm>

#include "config/topic_filter.hpp"

namespace unima::mqtt {

namespace {

// `topic` is `prefix` or a topic below it, level by level (`a/bc` is not under `a/b`).
bool under(std::string_view topic, std::string_view prefix) {
  return topic.starts_with(prefix) && (topic.size() == prefix.size() || topic[prefix.size()] == '/');
}

bool is_bridge_topic(std::string_view topic, const config::MqttConfig& mqtt) {
  if (topic.starts_with('$') || under(topic, config::sparkplug_topic_namespace)) return true;
  if (mqtt.discovery && under(topic, mqtt.discovery->prefix)) return true;
  // Of its own prefix, only reply/ and below is not the bridge's: status, birth, the bank
  // documents and set/… are.
  return under(topic, mqtt.topic) && !topic.substr(mqtt.topic.size()).starts_with("/reply/");
}

}  // namespace

ResponseTopicVerdict judge_response_topic(std::string_view topic, const config::MqttConfig& mqtt) {
  if (topic.empty() || topic.size() > max_response_topic_bytes || topic.find_first_of(std::string_view("+#\0", 3)) != std::string_view::npos)
    return ResponseTopicVerdict::not_a_topic;
  if (is_bridge_topic(topic, mqtt)) return ResponseTopicVerdict::bridge_topic;
  const auto listed = [topic](const std::string& filter) { return config::topic_matches_filter(filter, topic); };
  if (std::ranges::none_of(mqtt.response_topics, listed)) return ResponseTopicVerdict::not_listed;
  return ResponseTopicVerdict::answer_there;
}

std::string_view verdict_text(ResponseTopicVerdict verdict) {
  switch (verdict) {
    case ResponseTopicVerdict::answer_there: return "allowed";
    case ResponseTopicVerdict::not_a_topic: return "not a topic to publish on (empty, a wildcard, a NUL or too long)";
    case ResponseTopicVerdict::bridge_topic: return "one of the bridge's own topics";
    case ResponseTopicVerdict::not_listed: return "not in mqtt.response_topics";
  }
  return "refused";
}

}  // namespace unima::mqtt
