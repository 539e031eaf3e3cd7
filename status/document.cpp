#include "status/document.hpp"

namespace unima::status {

namespace {

template <class Part>
void put(nlohmann::json& j, const char* key, const std::optional<Part>& part) {
  if (part) j[key] = *part;
}

template <class Part>
void take(const nlohmann::json& j, const char* key, std::optional<Part>& part) {
  if (const auto at = j.find(key); at != j.end() && !at->is_null()) part = at->template get<Part>();
}

}  // namespace

void to_json(nlohmann::json& j, const Document& d) {
  j = d.bridge ? nlohmann::json(*d.bridge) : nlohmann::json::object();
  j["ports"] = d.ports;
  put(j, "lines", d.lines);
  put(j, "modbus", d.modbus);
  put(j, "indicators", d.indicators);
  put(j, "monitor", d.monitor);
  put(j, "unimabus", d.unimabus);
  put(j, "devices", d.devices);
  put(j, "modules", d.modules);
  put(j, "master", d.master);
  put(j, "gateway", d.gateway);
  put(j, "state", d.state);
  put(j, "mqtt", d.mqtt);
  put(j, "sparkplug", d.sparkplug);
  if (d.http.handshakes || d.http.logins) {
    auto& http = j["http"] = nlohmann::json::object();
    put(http, "handshakes", d.http.handshakes);
    put(http, "logins", d.http.logins);
  }
  put(j, "config_in_force", d.config_in_force);
}

void from_json(const nlohmann::json& j, Document& d) {
  d = {};
  if (!j.is_object()) return;
  if (!j.empty()) d.bridge = j.get<BridgeStatus>();
  std::optional<std::vector<PortStatus>> ports;
  take(j, "ports", ports);
  d.ports = ports.value_or(std::vector<PortStatus>{});
  take(j, "lines", d.lines);
  take(j, "modbus", d.modbus);
  take(j, "indicators", d.indicators);
  take(j, "monitor", d.monitor);
  take(j, "unimabus", d.unimabus);
  take(j, "devices", d.devices);
  take(j, "modules", d.modules);
  take(j, "master", d.master);
  take(j, "gateway", d.gateway);
  take(j, "state", d.state);
  take(j, "mqtt", d.mqtt);
  take(j, "sparkplug", d.sparkplug);
  if (const auto http = j.find("http"); http != j.end() && http->is_object()) {
    take(*http, "handshakes", d.http.handshakes);
    take(*http, "logins", d.http.logins);
  }
  take(j, "config_in_force", d.config_in_force);
}

}  // namespace unima::status
