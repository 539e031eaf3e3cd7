#include "unimabus/bus_status.hpp"

namespace unima::unimabus {

namespace {

template <class T>
std::optional<T> present(const nlohmann::json& j, const char* key) {
  return j.contains(key) ? std::optional(j.at(key).get<T>()) : std::nullopt;
}

}  // namespace

void to_json(nlohmann::json& j, const UnimabusStatus& s) {
  j = s.led;
  j["transport"] = s.transport;
  j["recording"] = s.recording;
  j["telegrams_ignored"] = s.telegrams_ignored;
  j["telegrams_refused"] = s.telegrams_refused;
  if (s.clients) j["clients"] = *s.clients;
}

void from_json(const nlohmann::json& j, UnimabusStatus& s) {
  s.led = j.get<status::Activity>();
  s.transport = j.value("transport", std::string{});
  s.recording = j.value("recording", std::optional<std::string>{});
  s.telegrams_ignored = j.value("telegrams_ignored", std::uint64_t{0});
  s.telegrams_refused = j.value("telegrams_refused", std::uint64_t{0});
  s.clients = present<std::uint64_t>(j, "clients");
}

void to_json(nlohmann::json& j, const DeviceStatus& s) {
  j = {{"bank", s.bank}, {"type", s.type}, {"online", s.online}};
  if (s.address) j["address"] = *s.address;
  if (s.telegrams) j["telegrams"] = *s.telegrams;
}

void from_json(const nlohmann::json& j, DeviceStatus& s) {
  s.bank = j.value("bank", std::string{});
  s.type = j.value("type", std::optional<std::string>{});
  s.address = present<std::uint64_t>(j, "address");
  s.online = j.value("online", false);
  s.telegrams = present<std::uint64_t>(j, "telegrams");
}

const std::vector<status::Statistic<UnimabusStatus>>& unimabus_statistics() {
  using enum status::MetricType;
  using status::Samples;
  static const std::vector<status::Statistic<UnimabusStatus>> all{
      {"telegrams_ignored_total", counter, "Telegrams for no configured device.",
       [](const UnimabusStatus& u, Samples& out) { out.add(u.telegrams_ignored); }},
      {"telegrams_refused_total", counter, "Telegrams refused (ambiguous address, bad offset).",
       [](const UnimabusStatus& u, Samples& out) { out.add(u.telegrams_refused); }},
      {"feed_clients", gauge, "Connected feed clients (UnimaBUS drivers).",
       [](const UnimabusStatus& u, Samples& out) { out.add(u.clients); }},
  };
  return all;
}

namespace {
status::Labels device_labels(const DeviceStatus& d) { return {{"bank", d.bank}, {"type", d.type.value_or("")}}; }
}  // namespace

// A D_N without a type is not configured: not a device.
const std::vector<status::Statistic<DeviceStatus>>& device_statistics() {
  using enum status::MetricType;
  using status::Samples;
  static const std::vector<status::Statistic<DeviceStatus>> all{
      {"device_online", gauge, "1 while a configured device D_N is on-line on UnimaBUS.",
       [](const DeviceStatus& d, Samples& out) {
         if (d.type) out.add(d.online, device_labels(d));
       }},
      {"device_telegrams_total", counter, "UnimaBUS telegrams taken into a device bank D_N.",
       [](const DeviceStatus& d, Samples& out) {
         if (d.type) out.add(d.telegrams, device_labels(d));
       }},
  };
  return all;
}

const std::vector<status::Statistic<ModuleStatus>>& module_statistics() {
  using enum status::MetricType;
  using status::Samples;
  static const std::vector<status::Statistic<ModuleStatus>> all{
      {"module_online", gauge, "1 while an I/O module S_N is on-line on UnimaBUS.",
       [](const ModuleStatus& m, Samples& out) { out.add(m.online, {{"bank", m.bank}}); }},
      {"module_telegrams_total", counter, "UnimaBUS telegrams taken into an I/O module bank S_N.",
       [](const ModuleStatus& m, Samples& out) { out.add(m.telegrams, {{"bank", m.bank}}); }},
  };
  return all;
}

}  // namespace unima::unimabus
