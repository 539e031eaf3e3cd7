#pragma once
// The running bridge: the banks of one config, the UnimaBUS transport feeding them, and
// the Modbus ports serving them, on one io_context. A reload builds the new config's banks
// beside the old, carries the values over, and swaps; ports whose settings did not change
// keep their connections.

#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "config/config.hpp"
#include "config/register_map.hpp"
#include "platform/asio.hpp"
#include "io/control_socket.hpp"
#include "io/error_hold.hpp"
#include "io/north/http_server.hpp"
#include "io/north/mqtt_client.hpp"
#include "mqtt/bank_documents.hpp"
#include "values/value_model.hpp"
#include "io/lazy_deadline.hpp"
#include "monitor/monitor.hpp"
#include "io/modbus/rtu_slave_port.hpp"
#include "io/modbus/master_port.hpp"
#include "io/modbus/slave_context.hpp"
#include "io/state_file.hpp"
#include "io/modbus/tcp_slave_server.hpp"
#include "app/live_view.hpp"
#include "web/basic_auth.hpp"
#include "io/unimabus/telegram_recorder.hpp"
#include "unimabus/publisher.hpp"
#include "unimabus/telegram_intake.hpp"
#include "unimabus/transport.hpp"

namespace unima::banks {
class RegisterSpace;
}

namespace unima::app {

class Bridge {
 public:
  /// Builds everything and binds the ports; throws (std::exception) when it cannot.
  Bridge(asio::io_context& io, config::Config config);
  ~Bridge();

  void start();
  void stop();
  /// Switches to `config`; throws, leaving the running config untouched, when it cannot.
  void reload(config::Config config);

  const config::Config& config() const;
  /// The bound Modbus TCP port, 0 when there is no TCP slave.
  std::uint16_t tcp_port() const { return tcp_ ? tcp_->port() : 0; }
  /// The bound Modbus/TCP Security port, 0 when there is none.
  std::uint16_t tls_port() const { return tls_ ? tls_->port() : 0; }
  /// The front panel and counters as one JSON document (`unima-bridge status`);
  /// app/bridge_status.cpp.
  std::string status_document() const;
  /// The same document as JSON, for what is built from it (/metrics, the front panel).
  nlohmann::json status_json() const;
  /// What the HTTP server answers for `target` (app/bridge_http.cpp).
  io::HttpResponse http_response(std::string_view target);
  /// The bound HTTP port, 0 when there is none.
  std::uint16_t http_port() const { return http_ ? http_->port() : 0; }
  /// The Modbus master, in master mode; nullptr in slave mode.
  const io::MasterPort* master() const { return master_.get(); }

 private:
  struct Core;
  struct ReloadPlan;  // app/reload_plan.hpp
  std::unique_ptr<Core> build_core(config::Config config);
  ReloadPlan plan_reload(config::Config config);
  void commit(ReloadPlan plan);
  std::unique_ptr<unimabus::Transport> make_transport(const config::Config& config);
  std::unique_ptr<io::TcpSlaveServer> make_tcp_server(const config::Config& config);
  std::unique_ptr<io::TcpSlaveServer> make_tls_server(const config::Config& config);
  /// The HTTP server of `config` (http.tls loaded); throws when it cannot be made.
  std::unique_ptr<io::HttpServer> make_http_server(const config::Config& config);
  std::unique_ptr<io::HttpServer> serve_http(const io::HttpOptions& options);
  /// `http.users` of `config`, read; nullopt when there is none. Throws when it cannot be
  /// read, unless `running` (the same file, read before) can stay: then that is kept, logged.
  std::optional<web::BasicAuth> read_http_users(const config::Config& config, const config::Config* running) const;
  /// The MQTT client of `config` (app/bridge_mqtt.cpp); null without `mqtt`.
  std::unique_ptr<io::MqttClient> make_mqtt(const config::Config& config);
  /// The bank documents of the running config, what is due of them published (every 100 ms).
  void publish_mqtt();
  void take_command(std::string_view topic, std::string_view payload);
  void mqtt_tick();
  /// The running config's register map and what is published of it (after each load).
  void lay_out();
  void lay_out_mqtt();
  /// Who may ask (app/bridge_http.cpp): nullopt lets the request through.
  std::optional<io::HttpResponse> http_gate(std::string_view authorization, const std::string& peer);
  void heartbeat();
  /// What the front page shows now (app/bridge_http.cpp).
  LiveSnapshot live_snapshot() const;
  std::shared_ptr<asio::ssl::context> renewed_tls_context(const config::TlsSlaveConfig& tls) const;
  std::unique_ptr<io::RtuSlavePort> make_rtu_port(const config::Config& config);
  std::shared_ptr<io::MasterPort> make_master(const config::Config& config);
  io::SlaveContext slave_context();
  io::SlaveContext rtu_context();
  void on_foreign_exchange(std::span<const std::uint8_t> query, std::span<const std::uint8_t> response);
  std::string on_telegram(const unimabus::Telegram& telegram);
  void expire_presence();
  void log_presence(const std::vector<unimabus::TelegramIntake::PresenceChange>& changes) const;
  std::unique_ptr<io::ControlSocket> make_control_socket(const std::string& path);
  std::unique_ptr<io::TelegramRecorder> make_recorder(const config::Config& config) const;
  void restore_state();

  asio::io_context& io_;
  std::unique_ptr<Core> core_;
  io::ErrorHold error_hold_;
  std::unique_ptr<monitor::Monitor> monitor_;  // before the ports, whose hook points at it
  std::unique_ptr<io::StateFile> state_;       // before the ports, which wait for it to answer writes
  unimabus::Publisher publisher_;  // before the transport it publishes to
  std::unique_ptr<unimabus::Transport> transport_;
  std::unique_ptr<io::TelegramRecorder> recorder_;  // unimabus.record
  std::unique_ptr<io::TcpSlaveServer> tcp_;
  std::unique_ptr<io::TcpSlaveServer> tls_;  // Modbus/TCP Security (SPEC §11)
  std::unique_ptr<io::RtuSlavePort> rtu_;
  std::shared_ptr<io::MasterPort> master_;
  io::LazyDeadline presence_timer_;  // at the next moment a device can go off-line
  bool started_ = false;
  std::unique_ptr<io::ControlSocket> control_;
  std::unique_ptr<io::HttpServer> http_;
  LiveView live_;  // the front pages listening to /api/events
  std::optional<web::BasicAuth> http_users_;  // http.users; nullopt: the HTTP server asks no one
  std::unique_ptr<io::MqttClient> mqtt_;         // SPEC §12
  std::vector<config::MapRow> register_rows_;    // the running config's register map: the page, /api/registers
  values::ValueModel value_model_;               // its values: the page, /api/registers, MQTT (SPEC §17)
  std::vector<banks::BankId> mqtt_banks_;        // the banks published of them
  std::optional<mqtt::PublishSchedule> mqtt_schedule_;
  asio::steady_timer mqtt_timer_;
  // The loop's heartbeat: /healthz reports a stall when it has not beaten for 2 s.
  asio::steady_timer heartbeat_timer_;
  std::chrono::steady_clock::time_point last_turn_ = std::chrono::steady_clock::now();
  std::chrono::milliseconds last_stall_{0};
  std::chrono::steady_clock::time_point stall_reported_until_{};
  static constexpr std::chrono::seconds stall_limit{2};
  static constexpr std::chrono::seconds stall_report_window{5};
  std::chrono::steady_clock::time_point started_at_ = std::chrono::steady_clock::now();
};

}  // namespace unima::app
