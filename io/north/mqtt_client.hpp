#pragma once
// An MQTT client on the daemon's event loop (SPEC §12): Debian's libmosquitto for the
// protocol, its socket driven by Asio (mosquitto_socket, mosquitto_loop_read/write/misc)
// and no thread of its own. The broker's name is looked up with Asio's resolver, so
// nothing on the loop waits for DNS; the TCP connect is non-blocking
// (mosquitto_connect_async). A lost or refused connection is tried again with back-off
// (1 s doubling to 60 s, ±25 % jitter); Modbus never waits for any of it.
//
// The will is `offline` on the status topic, retained; a connection publishes `online`
// there, and stop() publishes `offline` before a clean disconnect.

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "platform/asio.hpp"

struct mosquitto;

namespace unima::io {

struct MqttClientOptions {
  std::string host;   // a name or an address
  std::uint16_t port = 1883;
  bool tls = false;
  std::string ca, certificate, key;  // PEM files for mqtts (certificate and key optional)
  std::string client_id;
  std::string username;  // empty: none
  std::string password;
  int version = 4;  // 4: MQTT 3.1.1; 5: MQTT 5
  std::string status_topic;  // <prefix>/status; empty: no status messages and no will of its own (Sparkplug's is the NDEATH)
  std::chrono::seconds keepalive{30};
};

class MqttClient {
 public:
  MqttClient(asio::io_context& io, MqttClientOptions options);
  ~MqttClient();

  void start();
  /// `offline` on the status topic, a clean disconnect (the broker drops the will).
  void stop();

  bool connected() const { return connected_; }
  /// Queues a QoS 1 message; false (nothing queued) while not connected: the caller keeps
  /// the latest values and publishes them all when on_connected says so.
  bool publish(const std::string& topic, std::string_view payload, bool retain);
  /// True while what was published has not all gone to the socket (a slow broker): the
  /// caller publishes its latest state later instead of queueing more.
  bool backlogged() const;
  /// Called on each (re)connection, after `online`.
  void on_connected(std::function<void()> handler) { on_connected_ = std::move(handler); }
  /// A will for each CONNECT, asked for just before it (Sparkplug: the NDEATH of the coming
  /// session, whose bdSeq each CONNECT counts); it takes the place of the status topic's.
  struct Will {
    std::string topic;
    std::string payload;
    int qos = 1;
    bool retain = false;
  };
  void will_for_each_connect(std::function<Will()> make) { make_will_ = std::move(make); }
  /// QoS 0, never retained (Sparkplug's births and data, §4.1 of its specification); false
  /// while not connected.
  bool publish_at_most_once(const std::string& topic, std::string_view payload);
  /// One more pattern subscribed on each connection, its messages to subscribe()'s handler.
  void subscribe_also(std::string pattern) { more_subscriptions_.push_back(std::move(pattern)); }
  /// Subscribes `pattern` (QoS 1) on each connection; messages go to `handler`.
  void subscribe(std::string pattern, std::function<void(std::string_view topic, std::string_view payload)> handler) {
    subscription_ = std::move(pattern);
    on_message_ = std::move(handler);
  }

  struct Counters {
    std::uint64_t connections = 0;
    std::uint64_t drops = 0;
    std::uint64_t published = 0;
  };
  const Counters& counters() const { return counters_; }
  const MqttClientOptions& options() const { return options_; }
  /// Why the last attempt or connection failed; empty while connected.
  const std::string& last_error() const { return last_error_; }
  std::optional<std::chrono::system_clock::time_point> connected_since() const { return connected_since_; }

 private:
  mosquitto* make_handle();
  void tick();
  void resolve();
  void connect(const std::string& address);
  void watch();
  void after_io(int rc);
  void lost(const std::string& why);
  void retry_later();
  void release_socket();
  void handle_connack(int rc);
  void handle_disconnect(int rc);

  asio::io_context& io_;
  MqttClientOptions options_;
  mosquitto* mosq_ = nullptr;
  asio::ip::tcp::resolver resolver_;
  std::optional<asio::posix::stream_descriptor> socket_;
  bool reading_ = false;
  bool writing_ = false;
  asio::steady_timer misc_timer_;   // keep-alive pings, once a second
  asio::steady_timer retry_timer_;
  std::chrono::milliseconds backoff_{1000};
  std::minstd_rand jitter_{std::random_device{}()};
  bool running_ = false;
  bool connected_ = false;
  bool drop_logged_ = false;  // the log says a drop once until the next connection
  std::optional<std::chrono::system_clock::time_point> connected_since_;
  std::string last_error_;
  std::string refusal_;  // why the broker refused the last CONNECT, for lost()
  Counters counters_;
  std::function<void()> on_connected_;
  std::string subscription_;
  std::function<void(std::string_view, std::string_view)> on_message_;
  std::function<Will()> make_will_;
  std::vector<std::string> more_subscriptions_;
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
};

}  // namespace unima::io
