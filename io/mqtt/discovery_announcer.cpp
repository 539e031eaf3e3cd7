#include "io/mqtt/discovery_announcer.hpp"

#include <algorithm>

namespace unima::io {

void DiscoveryAnnouncer::serve(std::vector<mqtt::DiscoveryMessage> messages) {
  for (auto& topic : mqtt::withdrawn_topics(served_, messages))
    if (std::find(withdrawn_.begin(), withdrawn_.end(), topic) == withdrawn_.end()) withdrawn_.push_back(std::move(topic));
  // A config served again (a reload undone before the withdrawal went) is not withdrawn.
  std::erase_if(withdrawn_, [&](const std::string& topic) {
    return std::any_of(messages.begin(), messages.end(), [&](const auto& message) { return message.topic == topic; });
  });
  served_ = std::move(messages);
}

void DiscoveryAnnouncer::announce(MqttClient& client) {
  if (!client.connected()) return;
  std::erase_if(withdrawn_, [&](const std::string& topic) { return client.publish(topic, "", true); });
  for (const auto& message : served_) client.publish(message.topic, message.payload, true);
}

}  // namespace unima::io
