#include "metrics/prometheus.hpp"

#include <chrono>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "monitor/monitor_line.hpp"

namespace unima::metrics {

namespace {

using Labels = std::vector<std::pair<std::string, std::string>>;

// Label values may hold anything a config names (a device type, a path): \, " and a
// newline are escaped as the format demands.
std::string escaped(const std::string& value) {
  std::string out;
  for (const char c : value) {
    if (c == '\\') out += "\\\\";
    else if (c == '"') out += "\\\"";
    else if (c == '\n') out += "\\n";
    else out += c;
  }
  return out;
}

class Exposition {
 public:
  /// Starts a family: its HELP and TYPE lines.
  Exposition& family(const std::string& name, const char* type, const char* help) {
    name_ = "unima_bridge_" + name;
    text_ += fmt::format("# HELP {} {}\n# TYPE {} {}\n", name_, help, name_, type);
    return *this;
  }
  /// `suffix`: a summary's "_sum" or "_count" after the family's name.
  Exposition& sample(const nlohmann::json& value, const Labels& labels = {}, const char* suffix = "") {
    if (!value.is_number() && !value.is_boolean()) return *this;  // absent: left out
    text_ += name_;
    text_ += suffix;
    if (!labels.empty()) {
      text_ += '{';
      for (std::size_t i = 0; i < labels.size(); ++i)
        text_ += fmt::format("{}{}=\"{}\"", i ? "," : "", labels[i].first, escaped(labels[i].second));
      text_ += '}';
    }
    text_ += ' ';
    text_ += value.is_boolean() ? (value.get<bool>() ? "1" : "0") : value.dump();
    text_ += '\n';
    return *this;
  }
  std::string take() { return std::move(text_); }

 private:
  std::string name_;
  std::string text_;
};

const nlohmann::json& field(const nlohmann::json& object, const char* key) {
  static const nlohmann::json absent;
  return object.is_object() && object.contains(key) ? object.at(key) : absent;
}

std::string text(const nlohmann::json& value) { return value.is_string() ? value.get<std::string>() : value.dump(); }

// A time of the status document ("2026-11-27T10:35:19.501234Z") as Prometheus keeps times:
// Unix seconds; none (null): absent, and the sample left out.
nlohmann::json unix_seconds(const nlohmann::json& time) {
  if (!time.is_string()) return {};
  const auto parsed = monitor::parse_utc_time(time.get<std::string>());
  if (!parsed) return {};
  return std::chrono::duration<double>(parsed->time_since_epoch()).count();
}

}  // namespace

std::string prometheus_text(const nlohmann::json& status) {
  Exposition out;
  out.family("uptime_seconds", "gauge", "Seconds since the daemon started.").sample(field(status, "uptime_s"));
  out.family("resident_memory_bytes", "gauge", "Resident set size of the daemon.").sample(field(status, "rss_bytes"));
  out.family("modbus_error", "gauge", "The Modbus error bit (C+0x13 bit 15, the front panel's Error LED).")
      .sample(field(status, "error"));

  const auto& ports = field(status, "ports");
  out.family("modbus_transactions_total", "counter", "Modbus transactions by port and monitor state.");
  for (const auto& port : ports.is_array() ? ports : nlohmann::json::array())
    for (const auto& [key, value] : port.items())
      if (key != "port" && key != "transactions" && key != "clients" && value.is_number())
        out.sample(value, {{"port", text(field(port, "port"))}, {"state", key}});
  out.family("modbus_clients", "gauge", "Connected Modbus clients by port.");
  for (const auto& port : ports.is_array() ? ports : nlohmann::json::array())
    out.sample(field(port, "clients"), {{"port", text(field(port, "port"))}});

  // TLS handshakes (SPEC §11; tls/handshake_limiter), by port: the Modbus/TCP Security
  // port's, and HTTPS' as port "https".
  std::vector<std::pair<std::string, const nlohmann::json*>> handshakes;
  if (ports.is_array())  // ports itself, not a copy: the pointers outlive the loop
    for (const auto& port : ports)
      if (field(port, "handshakes").is_object()) handshakes.emplace_back(text(field(port, "port")), &field(port, "handshakes"));
  if (const auto& https = field(field(status, "http"), "handshakes"); https.is_object()) handshakes.emplace_back("https", &https);
  out.family("tls_handshakes_total", "counter", "TLS handshakes completed, by port.");
  for (const auto& [port, h] : handshakes) out.sample(field(*h, "completed"), {{"port", port}});
  out.family("tls_handshakes_failed_total", "counter",
             "TLS handshakes started and not completed (an error, the deadline, the client left), by port.");
  for (const auto& [port, h] : handshakes) out.sample(field(*h, "failed"), {{"port", port}});
  out.family("tls_handshakes_refused_total", "counter",
             "TLS connections closed at accept because their host or the port had as many handshakes as allowed, by port and limit.");
  for (const auto& [port, h] : handshakes) {
    const auto& refused = field(*h, "refused");
    if (!refused.is_object()) continue;
    for (const auto& [limit, value] : refused.items()) out.sample(value, {{"port", port}, {"limit", limit}});
  }
  out.family("tls_handshakes_in_progress", "gauge", "TLS handshakes in progress, by port.");
  for (const auto& [port, h] : handshakes) out.sample(field(*h, "in_progress"), {{"port", port}});

  const auto& devices = field(status, "devices");
  out.family("device_online", "gauge", "1 while a configured device D_N is on-line on UnimaBUS.");
  for (const auto& d : devices.is_array() ? devices : nlohmann::json::array())
    if (field(d, "type").is_string()) out.sample(field(d, "online"), {{"bank", text(field(d, "bank"))}, {"type", text(field(d, "type"))}});
  out.family("device_telegrams_total", "counter", "UnimaBUS telegrams taken into a device bank D_N.");
  for (const auto& d : devices.is_array() ? devices : nlohmann::json::array())
    if (field(d, "type").is_string()) out.sample(field(d, "telegrams"), {{"bank", text(field(d, "bank"))}, {"type", text(field(d, "type"))}});
  const auto& modules = field(status, "modules");
  out.family("module_online", "gauge", "1 while an I/O module S_N is on-line on UnimaBUS.");
  for (const auto& m : modules.is_array() ? modules : nlohmann::json::array()) out.sample(field(m, "online"), {{"bank", text(field(m, "bank"))}});
  out.family("module_telegrams_total", "counter", "UnimaBUS telegrams taken into an I/O module bank S_N.");
  for (const auto& m : modules.is_array() ? modules : nlohmann::json::array())
    out.sample(field(m, "telegrams"), {{"bank", text(field(m, "bank"))}});

  const auto& unimabus = field(status, "unimabus");
  out.family("telegrams_ignored_total", "counter", "Telegrams for no configured device.")
      .sample(field(unimabus, "telegrams_ignored"));
  out.family("telegrams_refused_total", "counter", "Telegrams refused (ambiguous address, bad offset).")
      .sample(field(unimabus, "telegrams_refused"));
  out.family("feed_clients", "gauge", "Connected feed clients (UnimaBUS drivers).").sample(field(unimabus, "clients"));

  const auto& master = field(status, "master");
  for (const auto& [name, help] :
       {std::pair{"requests", "Requests the master sent to a foreign slave, retries and probes included."},
        std::pair{"answered", "Good answers from a foreign slave."},
        std::pair{"timeouts", "Requests to a foreign slave that timed out."},
        std::pair{"exceptions", "Exception answers from a foreign slave."},
        std::pair{"bad_frames", "Bad frames from a foreign slave (CRC, length, function, address)."}}) {
    out.family(fmt::format("master_{}_total", name), "counter", help);
    for (const auto& d : master.is_array() ? master : nlohmann::json::array())
      out.sample(field(d, name), {{"device", text(field(d, "device"))}});
  }

  // modbus.gateway (SPEC §14), by unit id: what its clients got, what waits, whether it answers.
  const auto& gateway_units = field(field(status, "gateway"), "units");
  const auto& units = gateway_units.is_array() ? gateway_units : nlohmann::json::array();
  const auto unit_label = [](const nlohmann::json& u) { return Labels{{"unit", text(field(u, "unit"))}}; };
  for (const auto& [name, help] :
       {std::pair{"requests", "Requests the gateway sent on the line to a unit (never retried)."},
        std::pair{"answered", "Answers with data from a unit behind the gateway."},
        std::pair{"exceptions", "The slave's own exception answers, passed back to the client."},
        std::pair{"timeouts", "Forwarded requests without an answer (the client got exception 0B)."},
        std::pair{"bad_frames", "Forwarded requests answered with a bad frame: CRC, length, address (the client got 0B)."},
        std::pair{"busy", "Requests that could not start on the line within wait (the client got exception 06)."},
        std::pair{"cache_hits", "Reads answered from the gateway's cache, without the line."}}) {
    out.family(fmt::format("gateway_{}_total", name), "counter", help);
    for (const auto& u : units) out.sample(field(u, name), unit_label(u));
  }
  out.family("gateway_queue_depth", "gauge", "Requests for a unit waiting for the line now.");
  for (const auto& u : units) out.sample(field(u, "queue_depth"), unit_label(u));
  out.family("gateway_answering", "gauge", "1 while a unit behind the gateway answers; 0 after 3 failed requests in a row.");
  for (const auto& u : units) out.sample(field(u, "state").is_string() ? nlohmann::json(field(u, "state") == "answering") : nlohmann::json(), unit_label(u));
  const auto seconds = [](const nlohmann::json& ms) { return ms.is_number() ? nlohmann::json(ms.get<double>() / 1000.0) : nlohmann::json(); };
  out.family("gateway_wait_seconds", "summary", "Time a forwarded request waited for the line, from the client to its frame.");
  for (const auto& u : units) {
    const auto& wait = field(u, "wait_ms");
    out.sample(seconds(field(wait, "sum")), unit_label(u), "_sum").sample(field(wait, "count"), unit_label(u), "_count");
  }
  out.family("gateway_wait_max_seconds", "gauge", "The longest a forwarded request for a unit has waited for the line.");
  for (const auto& u : units) out.sample(seconds(field(field(u, "wait_ms"), "max")), unit_label(u));

  const auto& monitor = field(status, "monitor");
  out.family("monitor_lines_written_total", "counter", "Monitor lines written.").sample(field(monitor, "written"));
  out.family("monitor_lines_dropped_total", "counter", "Monitor lines dropped because the writer fell behind.")
      .sample(field(monitor, "dropped"));

  const auto& state = field(status, "state");
  out.family("state_records_total", "counter", "Writes recorded in the state file.").sample(field(state, "records"));
  out.family("state_syncs_total", "counter", "fdatasync calls of the state file.").sample(field(state, "syncs"));
  out.family("state_failures_total", "counter", "State file writes that failed.").sample(field(state, "failures"));

  if (const auto& mqtt = field(status, "mqtt"); mqtt.is_object()) {
    out.family("mqtt_connected", "gauge", "1 while the MQTT client is connected to its broker.").sample(field(mqtt, "connected"));
    out.family("mqtt_connections_total", "counter", "Connections made to the MQTT broker.").sample(field(mqtt, "connections"));
    out.family("mqtt_drops_total", "counter", "Connections to the MQTT broker that dropped.").sample(field(mqtt, "drops"));
    out.family("mqtt_published_total", "counter", "MQTT messages handed to the broker's connection.").sample(field(mqtt, "published"));
    out.family("mqtt_session_takeovers_total", "counter",
               "Times the MQTT broker gave the bridge's session to another client with its client id.")
        .sample(field(mqtt, "session_takeovers"));
    out.family("mqtt_state_since_timestamp_seconds", "gauge",
               "When the MQTT client's present state (mqtt_connected 1 or 0) began, in Unix seconds.")
        .sample(unix_seconds(field(mqtt, "since")));
    out.family("mqtt_last_session_takeover_timestamp_seconds", "gauge",
               "When the MQTT broker last gave the bridge's session to another client, in Unix seconds (none yet: absent).")
        .sample(unix_seconds(field(mqtt, "last_takeover")));
    if (const auto& buffer = field(mqtt, "buffer"); buffer.is_object()) {
      out.family("mqtt_buffer_bytes", "gauge", "Bytes of history in the MQTT buffer not yet acknowledged by the broker.")
          .sample(field(buffer, "bytes"));
      out.family("mqtt_buffer_messages", "gauge", "Documents in the MQTT buffer not yet acknowledged by the broker.")
          .sample(field(buffer, "messages"));
      out.family("mqtt_buffer_dropped_total", "counter", "Documents the full MQTT buffer dropped (the oldest first).")
          .sample(field(buffer, "dropped"));
      out.family("mqtt_buffer_history_sent_total", "counter", "History messages the broker acknowledged.")
          .sample(field(buffer, "history_sent"));
      out.family("mqtt_buffer_syncs_total", "counter", "fdatasync calls of the MQTT buffer (at most one a second).")
          .sample(field(buffer, "syncs"));
      out.family("mqtt_buffer_failures_total", "counter", "MQTT buffer writes or reads the disk refused.")
          .sample(field(buffer, "failures"));
    }
  }
  if (const auto& sparkplug = field(status, "sparkplug"); sparkplug.is_object()) {
    out.family("sparkplug_connected", "gauge", "1 while the Sparkplug B edge node is connected to its broker.")
        .sample(field(sparkplug, "connected"));
    out.family("sparkplug_born", "gauge", "1 while the edge node's NBIRTH stands (connected, and its primary host online).")
        .sample(field(sparkplug, "born"));
    out.family("sparkplug_bd_seq", "gauge", "The bdSeq of the edge node's present MQTT connection (0-255).")
        .sample(field(sparkplug, "bdSeq"));
    out.family("sparkplug_seq", "gauge", "The seq the edge node's next message carries (0-255).").sample(field(sparkplug, "seq"));
    out.family("sparkplug_state_since_timestamp_seconds", "gauge",
               "When the edge node's present state (sparkplug_connected 1 or 0) began, in Unix seconds.")
        .sample(unix_seconds(field(sparkplug, "since")));
    out.family("sparkplug_connections_total", "counter", "Connections made to the Sparkplug broker.")
        .sample(field(sparkplug, "connections"));
    out.family("sparkplug_births_total", "counter", "NBIRTH and DBIRTH messages published.").sample(field(sparkplug, "births"));
    out.family("sparkplug_data_total", "counter", "DDATA messages published.").sample(field(sparkplug, "data"));
    out.family("sparkplug_device_deaths_total", "counter", "DDEATH messages published.").sample(field(sparkplug, "deaths"));
    out.family("sparkplug_commands_total", "counter",
               "NCMD/DCMD metrics taken (a rebirth, a write) or refused, and command messages malformed.");
    for (const auto* outcome : {"taken", "refused", "malformed"})
      out.sample(field(field(sparkplug, "commands"), outcome), {{"outcome", outcome}});
  }
  if (const auto& logins = field(field(status, "http"), "logins"); logins.is_object()) {
    out.family("http_password_checks_total", "counter", "Password hashes of http.users computed (on the worker, not the loop).")
        .sample(field(logins, "checked"));
    out.family("http_password_checks_in_flight", "gauge", "Password checks queued or being computed.")
        .sample(field(logins, "in_flight"));
    out.family("http_logins_refused_total", "counter",
               "Requests with a name and password refused: wrong (401), too many from one host (429), too many at once (503).");
    for (const auto* reason : {"wrong", "peer_limited", "busy"}) out.sample(field(logins, reason), {{"reason", reason}});
  }
  return out.take();
}

}  // namespace unima::metrics
