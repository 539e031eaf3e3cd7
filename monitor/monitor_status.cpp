#include "monitor/monitor_status.hpp"

namespace unima::monitor {

void to_json(nlohmann::json& j, const IndicatorStatus& s) {
  j = {{"address", s.address}, {"register", s.reg}, {"value", s.value}, {"access", s.access}, {"time", s.time}};
}

void from_json(const nlohmann::json& j, IndicatorStatus& s) {
  s.address = j.value("address", std::uint64_t{0});
  s.reg = j.value("register", std::uint64_t{0});
  s.value = j.value("value", std::optional<std::uint64_t>{});
  s.access = j.value("access", std::optional<std::string>{});
  s.time = j.value("time", std::optional<std::string>{});
}

void to_json(nlohmann::json& j, const MonitorStatus& s) {
  j = {{"file", s.file},       {"stdout", s.to_stdout}, {"format", s.format}, {"filter", s.filter},
       {"queue", s.queue},     {"written", s.written},  {"dropped", s.dropped}};
}

void from_json(const nlohmann::json& j, MonitorStatus& s) {
  s.file = j.value("file", std::optional<std::string>{});
  s.to_stdout = j.value("stdout", false);
  s.format = j.value("format", std::string{});
  s.filter = j.value("filter", std::string{});
  s.queue = j.value("queue", std::uint64_t{0});
  s.written = j.value("written", std::uint64_t{0});
  s.dropped = j.value("dropped", std::uint64_t{0});
}

const std::vector<status::Statistic<MonitorStatus>>& monitor_statistics() {
  using enum status::MetricType;
  using status::Samples;
  static const std::vector<status::Statistic<MonitorStatus>> all{
      {"monitor_lines_written_total", counter, "Monitor lines written.",
       [](const MonitorStatus& m, Samples& out) { out.add(m.written); }},
      {"monitor_lines_dropped_total", counter, "Monitor lines dropped because the writer fell behind.",
       [](const MonitorStatus& m, Samples& out) { out.add(m.dropped); }},
  };
  return all;
}

}  // namespace unima::monitor
