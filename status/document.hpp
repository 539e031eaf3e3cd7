#pragma once
// The status document (SPEC §13) as one typed value: what `unima-bridge status --json` and
// /api/status print, /metrics exposes, the CLI panel and the page draw. app/bridge fills
// the bridge's own part, each service its part (io/service.hpp `describe`); every reader
// takes the parts, never a key. Each part is declared, with its JSON and its statistics,
// in the library of what it describes; this composes them, and its JSON is written and
// read here once (the CLI reads the document back from the control socket).
//
// A part a running bridge lacks (no MQTT, no gateway, ...) is absent, and so is its key.
//
// Pure: no clock, no I/O. A library of its own (unima_status_document): it sits above
// every part's library, while unima_status sits below them.

#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "master/gateway_status.hpp"
#include "monitor/monitor_status.hpp"
#include "mqtt/mqtt_status.hpp"
#include "remote/config_status.hpp"
#include "sparkplug/edge_status.hpp"
#include "state/state_status.hpp"
#include "status/activity.hpp"
#include "status/bridge_status.hpp"
#include "status/line_status.hpp"
#include "status/port_status.hpp"
#include "unimabus/bus_status.hpp"
#include "web/login_status.hpp"

namespace unima::status {

/// HTTP's part ("http"): HTTPS' handshakes with TLS on, the password checks with users.
struct HttpStatus {
  std::optional<HandshakeStatus> handshakes;
  std::optional<web::LoginStatus> logins;
};

struct Document {
  std::optional<BridgeStatus> bridge;  // the top-level keys; absent only in a document read from nothing
  std::vector<PortStatus> ports;       // always there, empty before any port counts
  std::optional<std::vector<LineStatus>> lines;  // each RS-485 line, modbus.rtu as `rtu`; absent without one
  std::optional<Activity> modbus;      // the Modbus LED
  std::optional<std::vector<monitor::IndicatorStatus>> indicators;
  std::optional<monitor::MonitorStatus> monitor;
  std::optional<unimabus::UnimabusStatus> unimabus;
  std::optional<std::vector<unimabus::DeviceStatus>> devices;
  std::optional<std::vector<unimabus::ModuleStatus>> modules;
  std::optional<std::vector<master::MasterDeviceStatus>> master;
  std::optional<master::GatewayStatus> gateway;
  std::optional<state::StateStatus> state;
  std::optional<mqtt::MqttStatus> mqtt;
  std::optional<sparkplug::EdgeStatus> sparkplug;
  HttpStatus http;  // "http" only when it holds a part
  std::optional<remote::ConfigStatus> config_in_force;  // "config_in_force": where the running config came from
};

void to_json(nlohmann::json& j, const Document& d);
/// Lenient: a key the document lacks (or null) leaves its part absent.
void from_json(const nlohmann::json& j, Document& d);

}  // namespace unima::status
