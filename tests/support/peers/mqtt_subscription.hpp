#pragma once
// The fleet's subscriber to the bridge's MQTT documents (SPEC §12): Debian's
// `mosquitto_sub` in the background, so that a test reads what a real client got, in the
// order the broker delivered it.

#include <filesystem>
#include <string>
#include <vector>

#include "tests/support/peers/mqtt_broker.hpp"

namespace unima::test_support {

/// mosquitto_sub on `topic` into `file`, subscribed when the constructor returns: it also
/// listens on a probe topic of its own, published to until the probe comes back.
class Subscription {
 public:
  /// `hex`: each payload as hex digits (binary payloads: Sparkplug's), not as it is.
  Subscription(const Broker& broker, const std::filesystem::path& file, const std::string& topic, bool hex = false);
  ~Subscription();
  Subscription(const Subscription&) = delete;
  Subscription& operator=(const Subscription&) = delete;

  /// What came so far: "topic payload" lines, whole ones only.
  std::string lines() const;

 private:
  std::filesystem::path file_;
  int pid_ = 0;
};

/// mosquitto_sub with a persistent session (-c, QoS 1, client id `client_id`) on `topics`
/// into `file`: what is published while it is away is queued for it by a broker that
/// keeps sessions. Subscribed when the constructor returns (the broker counts it).
class DurableSubscription {
 public:
  DurableSubscription(const Broker& broker, const std::filesystem::path& file, const std::string& client_id,
                      const std::vector<std::string>& topics);
  ~DurableSubscription();
  DurableSubscription(const DurableSubscription&) = delete;
  DurableSubscription& operator=(const DurableSubscription&) = delete;

  /// What came so far: "topic payload" lines, whole ones only.
  std::string lines() const;

 private:
  std::filesystem::path file_;
  int pid_ = 0;
};

/// `text` up to its last line end: what a writer still busy with its last line has done.
std::string whole_lines(std::string text);
/// The payloads of "topic payload" lines whose topic is `topic`.
std::vector<std::string> payloads(const std::string& lines, const std::string& topic);

}  // namespace unima::test_support
