#pragma once
// MQTT (`mqtt`, SPEC §12) as a service: the client, what it publishes — a bank whose
// values changed beyond their deadbands or whose on-line state changed, on the leading edge
// (at once when its last document is `report.min_interval` old, else when it is), each in
// full every `report.max_interval`, and all of them after each (re)connection
// (report::ReportSchedule, SPEC §21), woken by the store's changes (io/store_changes) and
// by a timer for the next due time only; each document timed when its values were
// measured (report::MeasurementTimes) — from the value model (values/) over the
// register store that Modbus reads, so a document and a Modbus read never disagree — and the commands
// it takes (`<prefix>/set/W/<n>`, `set/X/<bit>`), written through the one write path and
// answered on `<prefix>/set/result` or, for an MQTT 5 request that names one, on its
// Response Topic when mqtt/response_topic allows it there (SPEC §15); while too many
// commands wait for their answer (mqtt/command_flow), the client reads nothing more from
// the broker, and the per-command log line is rate-limited (platform/peer_warnings), so a
// burst of commands neither stalls the loop nor floods the log. Before all of it on
// each connection, the birth (`<prefix>/birth`, mqtt/birth.hpp); with `discovery`, Home
// Assistant's configs (io/mqtt/discovery_announcer). While the broker is unreachable the
// same documents go to the history buffer (`buffer`, SPEC §15: io/mqtt/history_buffer),
// sent as history once the live ones are out again (io/mqtt/history_sender). With
// `remote_config.mqtt`, configs from afar on `<prefix>/config/set` (mqtt/config_set), handed
// to the one flow of SPEC §19 (io/config_changes) and answered on `<prefix>/config/result`
// or an allowed Response Topic. A reload keeps the client (and its session) when the broker
// settings did not change; a reload to another config file says so in a new birth.

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/handler_guard.hpp"
#include "io/mqtt/discovery_announcer.hpp"
#include "io/mqtt/history_buffer.hpp"
#include "io/mqtt/history_sender.hpp"
#include "io/mqtt/mqtt_client.hpp"
#include "io/service.hpp"
#include "mqtt/bank_documents.hpp"
#include "mqtt/command_flow.hpp"
#include "report/measurement_times.hpp"
#include "report/report_schedule.hpp"

namespace unima::io {

class MqttService final : public Service {
 public:
  explicit MqttService(Runtime& runtime);

  void start() override;
  void stop() override;
  void stage(const Banks& next) override;
  void abandon() override;
  void commit(const Banks& previous) override;
  void describe(status::Document& status) const override;
  void probe(remote::ProbeFacts& facts) const override;
  /// A new birth when what it says changed (the config in force, the last change).
  void config_in_force_changed() override;

 private:
  std::unique_ptr<MqttClient> make_client(const config::Config& config);
  /// What the running config publishes, and a schedule that publishes it all first.
  void lay_out();
  /// Publishes what is due now and arms the timer for what is due next.
  void publish();
  void wake_at(report::ReportSchedule::Clock::time_point when);
  /// A command read from the broker: carried out now, or after those read before it that
  /// wait (`later_commands_`).
  void take_command(const MqttMessage& message);
  void carry_out(const MqttMessage& message);
  /// The client reads while mqtt::CommandFlow says it may; commands that wait are carried
  /// out then, a slice per turn of the loop.
  void follow_command_flow();
  void carry_out_later_commands();
  /// Publishes the answers that wait while the client's window has room: an answer never
  /// waits inside libmosquitto, whose every read takes as many packets as it holds
  /// messages (a burst's answers there made one read carry out thousands of commands).
  void send_answers();
  /// The Response Topic of a message (`what`: "command", "config") when the bridge may
  /// answer there, else empty: the answer goes to `fallback_topic`, as the warning says.
  std::string allowed_response_topic(const MqttMessage& message, std::string_view what, const std::string& fallback_topic);
  /// A message on `<prefix>/config/set`: a config to the flow, or a retained one cleared.
  void take_config(const MqttMessage& message);
  void subscribe_configs(MqttClient& client, const std::string& prefix);
  /// Subscribes or lets go of `<prefix>/config/set` as the running config says, for a
  /// client kept by a reload.
  void follow_remote_config(const config::Config& previous);
  /// The answer to a config, on the client there is now (a reload by the config itself may
  /// have replaced the one it came by), or kept for the next connection.
  void send_config_answer();
  std::string birth() const;
  /// The birth as the connection has it now: handed to it at connection or published since.
  std::string last_birth_;
  /// Documents go to the history buffer instead of the broker.
  bool buffering() const;

  Runtime& runtime_;
  std::unique_ptr<MqttClient> client_;
  std::vector<banks::BankId> banks_;  // the published banks, in the model's order
  std::optional<report::ReportSchedule> schedule_;
  report::MeasurementTimes measured_;  // of banks_
  DiscoveryAnnouncer discovery_;  // Home Assistant's configs (mqtt.discovery)
  std::unique_ptr<HistoryBuffer> buffer_;  // null: mqtt.buffer.file none, or no mqtt at the start
  std::unique_ptr<HistorySender> history_;
  bool history_waits_ = false;  // a new connection's history goes once its live documents are out
  asio::steady_timer timer_;  // the next due time: a capped change, the period, a backlog's retry
  std::optional<report::ReportSchedule::Clock::time_point> timer_due_;  // none: not armed
  bool started_ = false;
  std::uint64_t response_topics_refused_ = 0;  // of every client this service had
  mqtt::CommandFlow command_flow_;  // commands of every client this service had, waiting for their answer
  // Commands one read of the socket brought past the bound (libmosquitto reads as many
  // packets as it holds messages), in the order they came: carried out once the flow
  // allows, never dropped.
  struct LaterCommand {
    std::string topic, payload, response_topic, correlation_data;
  };
  std::deque<LaterCommand> later_commands_;
  bool carrying_out_later_ = false;  // a slice of them is posted
  std::deque<std::function<void()>> answers_;  // in the order the commands were answered
  bool sending_later_ = false;                  // send_answers is posted
  std::uint64_t retained_configs_dropped_ = 0;  // of every client this service had
  // The answer to a config from config/set that no connection has taken yet: the flow's end
  // may come while the client it came by is gone and the next not connected yet (a rollback
  // to another broker). One is enough: the flow takes one change at a time, and each new
  // change came over a connection that takes its answer at once.
  struct ConfigAnswer {
    std::string payload;           // remote::answer_json
    std::string response_topic;    // allowed when the config came; empty: result_topic
    std::string correlation_data;
    std::string result_topic;      // <prefix>/config/result of the prefix the config came by
  };
  std::optional<ConfigAnswer> config_answer_;
  HandlerGuard guard_;  // last: the posted slices see it expired as soon as the service is torn down
  // Staged by a reload:
  bool new_client_ = false;
  std::unique_ptr<MqttClient> next_client_;  // null with new_client_: no more MQTT
};

}  // namespace unima::io
