#include "metrics/prometheus.hpp"

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "status/document.hpp"

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

// A part of the status document, then each of its statistics written over every instance
// the document holds (none: the families' HELP and TYPE alone). `only_when_present`: a
// part that is off (mqtt, sparkplug, ...) has no families at all.
struct Part {
  std::function<void(const status::Document& status, Exposition& out)> write;
};

template <class Type>
Part part(std::vector<Type> (*instances)(const status::Document&), const std::vector<Statistic<Type>>& statistics,
          bool only_when_present = false) {
  return {[instances, &statistics, only_when_present](const status::Document& status, Exposition& out) {
    const auto all = instances(status);
    if (only_when_present && all.empty()) return;
    for (const auto& statistic : statistics) {
      Samples samples;
      for (const auto& one : all) statistic.samples(one, samples);
      out.family(statistic.name, statistic.type, statistic.help, samples);
    }
  }};
}

/// An optional part as none or one instance.
template <class Type>
std::vector<Type> one(const std::optional<Type>& part) {
  return part ? std::vector<Type>{*part} : std::vector<Type>{};
}

/// An optional list of parts as its instances.
template <class Type>
std::vector<Type> each(const std::optional<std::vector<Type>>& parts) {
  return parts.value_or(std::vector<Type>{});
}

// TLS handshakes (SPEC §11; tls/handshake_limiter), by port: the Modbus/TCP Security
// port's, and HTTPS' as port "https".
std::vector<status::PortHandshakes> handshakes(const status::Document& status) {
  std::vector<status::PortHandshakes> all;
  for (const auto& port : status.ports)
    if (port.handshakes) all.push_back({port.port, *port.handshakes});
  if (status.http.handshakes) all.push_back({"https", *status.http.handshakes});
  return all;
}

std::vector<master::GatewayUnitStatus> gateway_units(const status::Document& s) {
  return s.gateway ? s.gateway->units : std::vector<master::GatewayUnitStatus>{};
}

std::vector<mqtt::BufferStatus> mqtt_buffer(const status::Document& s) {
  return s.mqtt ? one(s.mqtt->buffer) : std::vector<mqtt::BufferStatus>{};
}

// Every family of /metrics, in the order of the exposition.
const std::vector<Part>& registry() {
  using Document = status::Document;
  static const std::vector<Part> all{
      part<status::BridgeStatus>([](const Document& s) { return one(s.bridge); }, status::bridge_statistics()),
      part<status::PortStatus>([](const Document& s) { return s.ports; }, status::port_statistics()),
      part<status::PortHandshakes>(handshakes, status::handshake_statistics()),
      part<status::LineStatus>([](const Document& s) { return each(s.lines); }, status::line_statistics(), true),
      part<unimabus::DeviceStatus>([](const Document& s) { return each(s.devices); }, unimabus::device_statistics()),
      part<unimabus::ModuleStatus>([](const Document& s) { return each(s.modules); }, unimabus::module_statistics()),
      part<unimabus::UnimabusStatus>([](const Document& s) { return one(s.unimabus); }, unimabus::unimabus_statistics()),
      part<master::MasterDeviceStatus>([](const Document& s) { return each(s.master); }, master::master_device_statistics()),
      part<master::GatewayUnitStatus>(gateway_units, master::gateway_unit_statistics()),
      part<monitor::MonitorStatus>([](const Document& s) { return one(s.monitor); }, monitor::monitor_statistics()),
      part<state::StateStatus>([](const Document& s) { return one(s.state); }, state::state_statistics()),
      part<mqtt::MqttStatus>([](const Document& s) { return one(s.mqtt); }, mqtt::mqtt_statistics(), true),
      part<mqtt::BufferStatus>(mqtt_buffer, mqtt::buffer_statistics(), true),
      part<sparkplug::EdgeStatus>([](const Document& s) { return one(s.sparkplug); }, sparkplug::edge_statistics(), true),
      part<web::LoginStatus>([](const Document& s) { return one(s.http.logins); }, web::login_statistics(), true),
      part<remote::ConfigStatus>([](const Document& s) { return one(s.config_in_force); }, remote::config_statistics(), true),
  };
  return all;
}

}  // namespace

std::string prometheus_text(const status::Document& status) {
  Exposition out;
  for (const auto& part : registry()) part.write(status, out);
  return out.take();
}

}  // namespace unima::metrics
