#pragma once
// The MQTT broker the bridge publishes to (SPEC §12): Debian's real `mosquitto`, one per
// test on a loopback port, so that the bridge meets a broker's own handling of retained
// messages, wills, TLS and passwords rather than an imitation of it. Its command-line
// clients publish and take a topic's first messages.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

namespace unima::test_support {

/// A mosquitto broker of the test's own, on 127.0.0.1, daemonized with a pid file;
/// `listener_extra` adds to its listener (TLS: cafile, certfile, keyfile, ...).
class Broker {
 public:
  explicit Broker(const std::filesystem::path& dir, const std::string& listener_extra = "");
  ~Broker();
  Broker(const Broker&) = delete;
  Broker& operator=(const Broker&) = delete;

  bool start();
  void stop();
  std::uint16_t port() const { return port_; }
  void signal(int signo) const;
  /// mosquitto_sub: the first `count` messages of `topic` ("topic payload" lines), waiting at most `seconds`.
  std::string subscribe(const std::string& topic, int count, int seconds = 5) const;
  /// How many subscriptions to exactly `topic` the broker has taken so far (its log says):
  /// a client counted here gets whatever is published to the topic from now on.
  std::size_t subscriptions_to(const std::string& topic) const;

 private:
  std::filesystem::path dir_;
  std::uint16_t port_;
};

/// The bridge's `mqtt` section the tests use: this broker, client site-17 under
/// fleet/site-17, documents every 60 s; `commands` for `commands: true`.
inline std::string site_17_mqtt(const Broker& broker, bool commands = false) {
  return "mqtt: { broker: 'mqtt://127.0.0.1:" + std::to_string(broker.port()) +
         "', client_id: site-17, topic: fleet/site-17, " + (commands ? "commands: true, " : "") + "publish: { period: 60s } }\n";
}

/// mosquitto_pub: one message, QoS 1; `retained`: kept in the broker's store too.
void publish(const Broker& broker, const std::string& topic, const std::string& payload, bool retained = false);

}  // namespace unima::test_support
