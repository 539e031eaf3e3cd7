#pragma once
// An MQTT client on the daemon's event loop (SPEC §12): Debian's libmosquitto for the
// protocol, its socket driven by Asio (mosquitto_socket, mosquitto_loop_read/write/misc)
// and no thread of its own. The broker's name is looked up with Asio's resolver, so
// nothing on the loop waits for DNS; the TCP connect is non-blocking
// (mosquitto_connect_async). A lost or refused connection is tried again with back-off
// (1 s doubling to 60 s, ±25 % jitter); Modbus never waits for any of it.
//
// The will is `offline` on the status topic, retained; a connection publishes the birth
// (SPEC §15), then `online` there, and only then takes anyone's publish(): nothing can go
// before them. stop() publishes `offline` before a clean disconnect.
//
// A broker that gave the session to another client with the same id
// (mqtt/session_takeover.hpp) is tried again no sooner than 30 s later, with an error in
// the log naming the id.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <unordered_set>
#include <utility>
#include <vector>

#include "io/loop_turn.hpp"
#include "mqtt/session_takeover.hpp"
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
  std::string birth_topic;   // <prefix>/birth; empty: no birth
  std::chrono::seconds keepalive{30};

  /// "host:port": how the log's peer warnings name the broker, one count per broker.
  std::string broker() const;
};

/// A message that came; MQTT 5's Response Topic, Correlation Data and User Properties when
/// it carried them.
struct MqttMessage {
  std::string_view topic;
  std::string_view payload;
  bool retained = false;  // from the broker's store, not published while subscribed
  std::string response_topic;    // empty: none (always with MQTT 3.1.1)
  std::string correlation_data;  // bytes, given back as they came
  std::vector<std::pair<std::string, std::string>> user_properties;  // name, value; in the order they came
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
  /// Queues a QoS 1 message, not retained, whose acknowledgement the caller follows: its
  /// message id, told to on_acknowledged when the broker's PUBACK comes; nullopt (nothing
  /// queued) while not connected. Ids are of this connection only.
  std::optional<int> publish_acknowledged(const std::string& topic, std::string_view payload);
  void on_acknowledged(std::function<void(int mid)> handler) { on_acknowledged_ = std::move(handler); }
  /// Called once everything published has gone to the socket after a write had to wait:
  /// a caller that stopped at backlogged() goes on.
  void on_drained(std::function<void()> handler) { on_drained_ = std::move(handler); }
  /// QoS 1 messages sent and not acknowledged yet, at most; more wait inside libmosquitto.
  static constexpr std::size_t in_flight_window = 256;
  /// A full window of QoS 1 messages waits for the broker's acknowledgement.
  bool window_full() const { return unacknowledged_.size() >= in_flight_window; }
  /// True while what was published has not all gone to the socket, or a full window of it
  /// waits for the broker's acknowledgement (a slow broker): the caller publishes its
  /// latest state later instead of queueing more.
  bool backlogged() const;
  /// While held, nothing more is read from the broker's socket: the messages wait there and
  /// in the broker (its flow control, QoS 1's included), and none read is ever dropped.
  /// Writes and the keep-alive go on. The MQTT service holds it while too many commands
  /// wait for their answer (mqtt/command_flow.hpp).
  void hold_reading(bool held);
  /// An answer to an MQTT 5 request (SPEC §15): QoS 1, not retained, with the request's
  /// correlation data; false when not connected or the broker cannot take `topic`.
  bool publish_response(const std::string& topic, std::string_view payload, std::string_view correlation_data);
  /// The birth's payload, made at each connection (the facts in it may have changed).
  void birth(std::function<std::string()> payload) { birth_ = std::move(payload); }
  /// Called on each (re)connection, after the birth and `online`.
  void on_connected(std::function<void()> handler) { on_connected_ = std::move(handler); }
  /// What a subscription does with retained messages. A command's topic takes none: a
  /// retained command would be carried out again at every start and reconnection, over
  /// what a Modbus master wrote since (SPEC §15; Sparkplug 3.0 forbids retained commands).
  /// With MQTT 5 the broker is asked not to send them (Retain Handling 2); any that comes
  /// anyway (MQTT 3.1.1) is dropped here, counted and warned about. `flagged` hands them
  /// to the handler with their flag (MqttMessage::retained), and with MQTT 5 asks the
  /// broker to keep the flag of a retained message published while subscribed too (Retain
  /// As Published), which MQTT 3.1.1 brokers clear: config/set clears such messages.
  enum class Retained { taken, dropped, flagged };
  /// Subscribes `pattern` (QoS 1) on each connection — at once too when connected —
  /// beside the patterns subscribed before; a message goes to the handler of each pattern
  /// it matches.
  void subscribe(std::string pattern, std::function<void(const MqttMessage&)> handler, Retained retained = Retained::taken);
  /// Takes `pattern` back (at once when connected); a message that matches it no more
  /// reaches its handler.
  void unsubscribe(const std::string& pattern);
  /// A will for each CONNECT, asked for just before it (Sparkplug: the NDEATH of the coming
  /// session, whose bdSeq each CONNECT counts); it takes the place of the status topic's.
  /// `make` hands the will to the callback it is given, on the loop, when it is ready — the
  /// CONNECT goes then (Sparkplug first makes the bdSeq durable, off the loop). A will
  /// handed over after stop() or a later attempt is dropped.
  struct Will {
    std::string topic;
    std::string payload;
    int qos = 1;
    bool retain = false;
  };
  using WillReady = std::function<void(Will)>;
  void will_for_each_connect(std::function<void(WillReady)> make) { make_will_ = std::move(make); }
  /// QoS 0, never retained (Sparkplug's births and data, §4.1 of its specification); false
  /// while not connected.
  bool publish_at_most_once(const std::string& topic, std::string_view payload);

  struct Counters {
    std::uint64_t connections = 0;
    std::uint64_t drops = 0;
    std::uint64_t published = 0;
    std::uint64_t session_takeovers = 0;
    std::uint64_t retained_commands_dropped = 0;
  };
  const Counters& counters() const { return counters_; }
  const MqttClientOptions& options() const { return options_; }
  /// Why the last attempt or connection failed; empty while connected.
  const std::string& last_error() const { return last_error_; }
  /// When the present state began: this connection, or (not connected) the start or the
  /// last drop — an operator asks how long the bridge has been cut off, not only whether.
  std::chrono::system_clock::time_point state_since() const { return state_since_; }
  /// When a broker last gave the session to another client; none yet: nullopt.
  std::optional<std::chrono::system_clock::time_point> last_takeover() const { return last_takeover_; }

 private:
  mosquitto* make_handle();
  void tick();
  void resolve();
  void connect(const std::string& address);
  void connect_now(const std::string& host);
  void watch();
  void after_io(int rc);
  void lost(const std::string& why);
  void drop_retained_command(std::string_view topic);
  struct Subscription;
  void send_subscribe(const Subscription& subscription);
  void retry_later();
  void release_socket();
  void handle_connack(int rc);
  void handle_disconnect(int rc);
  /// A QoS 1 publish, connected_ or not: only handle_connack sends before connected_.
  bool send(const std::string& topic, std::string_view payload, bool retain);
  void read();
  void end_read_when_spent();

  asio::io_context& io_;
  MqttClientOptions options_;
  mosquitto* mosq_ = nullptr;
  asio::ip::tcp::resolver resolver_;
  std::optional<asio::posix::stream_descriptor> socket_;
  bool reading_ = false;
  bool held_ = false;  // hold_reading
  TurnDeadline read_turn_;       // of the read under way
  bool read_cut_short_ = false;  // by its budget: more may be there, the socket readable or not
  std::unordered_set<int> unacknowledged_;  // message ids of QoS 1 publishes on this handle
  bool writing_ = false;
  asio::steady_timer misc_timer_;   // keep-alive pings, once a second
  asio::steady_timer retry_timer_;
  std::chrono::milliseconds backoff_{1000};
  std::minstd_rand jitter_{std::random_device{}()};
  bool running_ = false;
  bool connected_ = false;
  bool drop_logged_ = false;  // the log says a drop once until the next connection
  std::chrono::system_clock::time_point state_since_ = std::chrono::system_clock::now();
  std::string last_error_;
  std::string refusal_;  // why the broker refused the last CONNECT, for lost()
  mqtt::SessionTakeover takeover_;
  bool taken_over_ = false;  // the connection that ended last: its session was taken over
  std::optional<std::chrono::system_clock::time_point> last_takeover_;
  Counters counters_;
  std::function<std::string()> birth_;
  std::function<void()> on_connected_;
  std::function<void(int mid)> on_acknowledged_;
  std::function<void()> on_drained_;
  struct Subscription {
    std::string pattern;
    std::function<void(const MqttMessage&)> handler;
    Retained retained = Retained::taken;
  };
  std::vector<Subscription> subscriptions_;
  std::function<void(WillReady)> make_will_;
  std::uint64_t attempts_ = 0;  // a will handed over for an older attempt is dropped
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
};

}  // namespace unima::io
