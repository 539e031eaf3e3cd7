#pragma once
// Sparkplug B (`sparkplug`, SPEC §16) as a service: an MQTT connection of its own
// (io/mqtt/mqtt_client) to the section's broker, and the edge node's session
// (sparkplug/edge_session, which decides) over the value model (values/) that Modbus, the
// page and MQTT read too. When the banks change (io/store_changes, Runtime::changes) it asks the
// session what is due — DDATA of what changed, DDEATH/DBIRTH of a device that went or
// came, each device on the leading edge of `report.min_interval` and in full every
// `report.max_interval` (the session's report::ReportSchedule, as MQTT's documents) — and
// publishes it (QoS 0, as Sparkplug has births and data); a timer wakes it for the next
// due time only; births go the moment they are due. The will of each CONNECT is the NDEATH with that connection's bdSeq, which a
// small file beside the state file keeps across restarts (`<state file>.sparkplug-bdseq`),
// written and fdatasync'ed on a worker thread (io/cpu_worker) before the CONNECT goes.
// NCMD rebirth, DCMD writes through the one write path
// (as MQTT commands and Modbus writes), the primary host's STATE: all read here, decided
// by the session. A reload keeps the connection when the section did not change, and
// sends every birth again (the value model may have changed) with the new `report`.

#include <filesystem>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "io/cpu_worker.hpp"
#include "io/mqtt/mqtt_client.hpp"
#include "io/service.hpp"
#include "report/measurement_times.hpp"
#include "sparkplug/edge_session.hpp"
#include "sparkplug/rebirth_pacing.hpp"

namespace unima::io {

class SparkplugService final : public Service {
 public:
  explicit SparkplugService(Runtime& runtime);
  ~SparkplugService() override { *alive_ = false; }

  void start() override;
  void stop() override;
  void stage(const Banks& next) override;
  void abandon() override;
  void commit(const Banks& previous) override;
  void describe(status::Document& status) const override;
  void probe(remote::ProbeFacts& facts) const override;

 private:
  std::unique_ptr<MqttClient> make_client(const config::Config& config);
  /// The banks changed: what is due of it goes now, the rest when the session says.
  void banks_changed();
  /// report::MeasurementTimes of the banks now; their change counts, in the model's order.
  std::vector<std::uint64_t> note_measured();
  /// Publishes what the session has due now and arms the timer for what is due next.
  void publish_due();
  void wake_at(sparkplug::EdgeSession::Clock::time_point when);
  /// An NCMD rebirth: now, or once with those asked meanwhile (sparkplug/rebirth_pacing).
  void rebirth_asked();
  void take_message(std::string_view topic, std::string_view payload);
  void take_command(std::string_view device, std::string_view topic, std::string_view payload);
  /// The host went offline: the node says its death, disconnects, and connects again to
  /// wait for the host (outside libmosquitto's callback that told it).
  void die_and_reconnect();
  void publish_death();
  void will_of_next_connect(MqttClient::WillReady ready);

  Runtime& runtime_;
  std::unique_ptr<MqttClient> client_;
  std::optional<sparkplug::EdgeSession> session_;
  std::filesystem::path bd_seq_file_;  // empty: no state file, bdSeq counts from 0 at each start
  report::MeasurementTimes measured_;  // of the value model's banks, in its order
  asio::steady_timer due_timer_;  // the session's next due time: a held-back change, a max_interval, a backlog's retry
  std::optional<sparkplug::EdgeSession::Clock::time_point> timer_due_;  // none: not armed
  sparkplug::RebirthPacing rebirth_pacing_;
  asio::steady_timer rebirth_timer_;
  CpuWorker bd_seq_writer_;  // the bdSeq file's fdatasync, off the loop
  bool started_ = false;
  std::string dcmd_prefix_;  // spBv1.0/<group>/DCMD/<node>/
  // Staged by a reload:
  bool new_client_ = false;
  std::unique_ptr<MqttClient> next_client_;
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
};

}  // namespace unima::io
