#pragma once
// Home Assistant's discovery configs on the broker (SPEC §15, mqtt/discovery.hpp): all of
// them, retained, at each connection and whenever Home Assistant says `online` (it has
// started, and may have lost what it knew); after a reload, first an empty retained
// payload for each config the new config no longer serves — Home Assistant removes those
// entities — then the configs it serves. What could not go (no connection) goes at the
// next connection.

#include <string>
#include <vector>

#include "io/mqtt/mqtt_client.hpp"
#include "mqtt/discovery.hpp"

namespace unima::io {

class DiscoveryAnnouncer {
 public:
  /// The configs the running config serves; those of the last that it does not are
  /// withdrawn at the next announce().
  void serve(std::vector<mqtt::DiscoveryMessage> messages);
  /// Withdraws what is no longer served, then publishes every config; nothing while
  /// `client` is not connected.
  void announce(MqttClient& client);

 private:
  std::vector<mqtt::DiscoveryMessage> served_;
  std::vector<std::string> withdrawn_;
};

}  // namespace unima::io
