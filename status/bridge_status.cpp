#include "status/bridge_status.hpp"

namespace unima::status {

namespace {
const char* const rss_key = "rss_bytes";
}  // namespace

void to_json(nlohmann::json& j, const BridgeStatus& s) {
  j = {{"pid", s.pid},
       {"config", s.config},
       {"uptime_s", s.uptime_s},
       {"mode", s.mode},
       {"modbus_address", s.modbus_address},
       {"unimabus_address", s.unimabus_address},
       {"error", s.error},
       {"online_bits", s.online_bits}};
  if (s.rss_bytes) j[rss_key] = *s.rss_bytes;
}

void from_json(const nlohmann::json& j, BridgeStatus& s) {
  s.pid = j.value("pid", std::int64_t{0});
  s.config = j.value("config", std::string{});
  s.uptime_s = j.value("uptime_s", std::int64_t{0});
  s.rss_bytes = j.contains(rss_key) ? std::optional(j.at(rss_key).get<std::uint64_t>()) : std::nullopt;
  s.mode = j.value("mode", std::string{});
  s.modbus_address = j.value("modbus_address", std::uint64_t{0});
  s.unimabus_address = j.value("unimabus_address", std::uint64_t{0});
  s.error = j.value("error", false);
  s.online_bits = j.value("online_bits", std::uint64_t{0});
}

const std::vector<Statistic<BridgeStatus>>& bridge_statistics() {
  using enum MetricType;
  static const std::vector<Statistic<BridgeStatus>> all{
      {"uptime_seconds", gauge, "Seconds since the daemon started.",
       [](const BridgeStatus& s, Samples& out) { out.add(s.uptime_s); }},
      {"resident_memory_bytes", gauge, "Resident set size of the daemon.",
       [](const BridgeStatus& s, Samples& out) { out.add(s.rss_bytes); }},
      {"modbus_error", gauge, "The Modbus error bit (C+0x13 bit 15, the front panel's Error LED).",
       [](const BridgeStatus& s, Samples& out) { out.add(s.error); }},
  };
  return all;
}

}  // namespace unima::status
