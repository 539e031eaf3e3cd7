#pragma once
// A reload in two halves (SIGHUP, Bridge::reload): the plan builds every part of the new
// config that can fail — banks, monitor log, status socket, transport, TCP listener,
// master line — while the running bridge keeps serving; committing it then switches
// without a step that can fail. A plan dropped before commit (a step threw) gives back
// what it took: the running TCP slave, stopped so that the new one could bind its port,
// is brought back.

#include <memory>
#include <optional>

#include "app/bridge.hpp"
#include "app/bridge_core.hpp"
#include "app/rollback.hpp"

namespace unima::app {

struct Bridge::ReloadPlan {
  // First, so that it is undone last: after a new TCP listener on the same port is gone.
  Rollback restore_tcp;  // brings the running TCP slave back
  Rollback restore_tls;  // and the running TLS slave
  Rollback restore_http;  // and the running HTTP server
  std::unique_ptr<Core> core;
  std::unique_ptr<monitor::MonitorWriter> monitor_writer;  // when the log changed
  std::unique_ptr<unimabus::Transport> transport;          // when the transport changed; else keep
  bool same_recorder = true;
  std::unique_ptr<io::TelegramRecorder> recorder;          // when unimabus.record changed
  bool same_tcp = true;
  std::unique_ptr<io::TcpSlaveServer> tcp;                 // when the endpoint changed
  bool same_tls = true;
  std::unique_ptr<io::TcpSlaveServer> tls;                 // when its endpoint changed
  std::shared_ptr<asio::ssl::context> tls_context;         // same endpoint: the files read again (null: keep)
  bool same_http = true;
  std::unique_ptr<io::HttpServer> http;                    // when its endpoint changed
  std::shared_ptr<asio::ssl::context> http_tls_context;    // same endpoint: http.tls read again (null: keep)
  std::optional<web::BasicAuth> http_users;                // http.users read again (nullopt: no authentication)
  bool same_mqtt = true;
  std::unique_ptr<io::MqttClient> mqtt;                    // when mqtt changed (null: no more MQTT)
  bool same_rtu = true;
  std::shared_ptr<io::MasterPort> master;
  std::unique_ptr<io::ControlSocket> control;             // when status.socket changed (or had failed)
};

}  // namespace unima::app
