#include "metrics/prometheus.hpp"

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "master/gateway_status.hpp"
#include "monitor/monitor_status.hpp"
#include "mqtt/mqtt_status.hpp"
#include "sparkplug/edge_status.hpp"
#include "state/state_status.hpp"
#include "status/bridge_status.hpp"
#include "status/port_status.hpp"
#include "unimabus/bus_status.hpp"
#include "web/login_status.hpp"

namespace unima::metrics {

namespace {

using status::MetricType;
using status::Samples;
using status::Statistic;

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
  /// A family: its HELP and TYPE lines, then its samples.
  void family(const char* name, MetricType type, const char* help, const Samples& samples) {
    const auto full = std::string("unima_bridge_") + name;
    text_ += fmt::format("# HELP {} {}\n# TYPE {} {}\n", full, help, full, status::type_name(type));
    for (const auto& sample : samples.items()) {
      const auto& value = sample.value;
      if (!value.is_number() && !value.is_boolean()) continue;  // absent: left out
      text_ += full;
      text_ += sample.suffix;
      if (!sample.labels.empty()) {
        text_ += '{';
        for (std::size_t i = 0; i < sample.labels.size(); ++i)
          text_ += fmt::format("{}{}=\"{}\"", i ? "," : "", sample.labels[i].first, escaped(sample.labels[i].second));
        text_ += '}';
      }
      text_ += ' ';
      text_ += value.is_boolean() ? (value.get<bool>() ? "1" : "0") : value.dump();
      text_ += '\n';
    }
  }
  std::string take() { return std::move(text_); }

 private:
  std::string text_;
};

const nlohmann::json& field(const nlohmann::json& object, const char* key) {
  static const nlohmann::json absent;
  return object.is_object() && object.contains(key) ? object.at(key) : absent;
}

std::vector<nlohmann::json> elements(const nlohmann::json& array) {
  return array.is_array() ? std::vector<nlohmann::json>(array.begin(), array.end()) : std::vector<nlohmann::json>{};
}

// A part of the status document read as its type, then each of its statistics written
// over every instance the document holds (none: the families' HELP and TYPE alone).
// `only_when_present`: a part that is off (mqtt, sparkplug, ...) has no families at all.
struct Part {
  std::function<void(const nlohmann::json& status, Exposition& out)> write;
};

template <class Type>
Part part(std::function<std::vector<Type>(const nlohmann::json&)> instances, const std::vector<Statistic<Type>>& statistics,
          bool only_when_present = false) {
  return {[instances = std::move(instances), &statistics, only_when_present](const nlohmann::json& status, Exposition& out) {
    const auto all = instances(status);
    if (only_when_present && all.empty()) return;
    for (const auto& statistic : statistics) {
      Samples samples;
      for (const auto& one : all) statistic.samples(one, samples);
      out.family(statistic.name, statistic.type, statistic.help, samples);
    }
  }};
}

/// The object at `key` (of `parent`) as `Type`; none when it is not an object.
template <class Type>
std::vector<Type> object_at(const nlohmann::json& parent, const char* key) {
  const auto& value = field(parent, key);
  return value.is_object() ? std::vector<Type>{value.get<Type>()} : std::vector<Type>{};
}

/// The elements of the array at `key` as `Type`.
template <class Type>
std::vector<Type> array_at(const nlohmann::json& parent, const char* key) {
  std::vector<Type> all;
  for (const auto& element : elements(field(parent, key))) all.push_back(element.get<Type>());
  return all;
}

// The bridge's own part is the document's top level: an empty document has none.
std::vector<status::BridgeStatus> bridge(const nlohmann::json& document) {
  return document.is_object() && !document.empty() ? std::vector{document.get<status::BridgeStatus>()}
                                                    : std::vector<status::BridgeStatus>{};
}

// TLS handshakes (SPEC §11; tls/handshake_limiter), by port: the Modbus/TCP Security
// port's, and HTTPS' as port "https".
std::vector<status::PortHandshakes> handshakes(const nlohmann::json& status) {
  std::vector<status::PortHandshakes> all;
  for (const auto& port : array_at<status::PortStatus>(status, "ports"))
    if (port.handshakes) all.push_back({port.port, *port.handshakes});
  for (const auto& https : object_at<status::HandshakeStatus>(field(status, "http"), "handshakes")) all.push_back({"https", https});
  return all;
}

// Every family of /metrics, in the order of the exposition.
const std::vector<Part>& registry() {
  static const std::vector<Part> all{
      part<status::BridgeStatus>(bridge, status::bridge_statistics()),
      part<status::PortStatus>([](const nlohmann::json& s) { return array_at<status::PortStatus>(s, "ports"); },
                               status::port_statistics()),
      part<status::PortHandshakes>(handshakes, status::handshake_statistics()),
      part<unimabus::DeviceStatus>([](const nlohmann::json& s) { return array_at<unimabus::DeviceStatus>(s, "devices"); },
                                   unimabus::device_statistics()),
      part<unimabus::ModuleStatus>([](const nlohmann::json& s) { return array_at<unimabus::ModuleStatus>(s, "modules"); },
                                   unimabus::module_statistics()),
      part<unimabus::UnimabusStatus>([](const nlohmann::json& s) { return object_at<unimabus::UnimabusStatus>(s, "unimabus"); },
                                     unimabus::unimabus_statistics()),
      part<master::MasterDeviceStatus>([](const nlohmann::json& s) { return array_at<master::MasterDeviceStatus>(s, "master"); },
                                       master::master_device_statistics()),
      part<master::GatewayUnitStatus>(
          [](const nlohmann::json& s) { return array_at<master::GatewayUnitStatus>(field(s, "gateway"), "units"); },
          master::gateway_unit_statistics()),
      part<monitor::MonitorStatus>([](const nlohmann::json& s) { return object_at<monitor::MonitorStatus>(s, "monitor"); },
                                   monitor::monitor_statistics()),
      part<state::StateStatus>([](const nlohmann::json& s) { return object_at<state::StateStatus>(s, "state"); },
                               state::state_statistics()),
      part<mqtt::MqttStatus>([](const nlohmann::json& s) { return object_at<mqtt::MqttStatus>(s, "mqtt"); },
                             mqtt::mqtt_statistics(), true),
      part<mqtt::BufferStatus>([](const nlohmann::json& s) { return object_at<mqtt::BufferStatus>(field(s, "mqtt"), "buffer"); },
                               mqtt::buffer_statistics(), true),
      part<sparkplug::EdgeStatus>([](const nlohmann::json& s) { return object_at<sparkplug::EdgeStatus>(s, "sparkplug"); },
                                  sparkplug::edge_statistics(), true),
      part<web::LoginStatus>([](const nlohmann::json& s) { return object_at<web::LoginStatus>(field(s, "http"), "logins"); },
                             web::login_statistics(), true),
  };
  return all;
}

}  // namespace

std::string prometheus_text(const nlohmann::json& status) {
  Exposition out;
  for (const auto& part : registry()) part.write(status, out);
  return out.take();
}

}  // namespace unima::metrics
