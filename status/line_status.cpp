#include "status/line_status.hpp"

namespace unima::status {

void to_json(nlohmann::json& j, const LineStatus& s) {
  j = {{"line", s.name},
       {"role", s.role},
       {"device", s.device},
       {"settings", s.settings},
       {"open", s.open},
       {"frames_sent", s.counters.frames_sent},
       {"frames_received", s.counters.frames_received},
       {"errors", s.counters.errors},
       {"queue", s.queue}};
}

void from_json(const nlohmann::json& j, LineStatus& s) {
  s.name = j.value("line", std::string());
  s.role = j.value("role", std::string());
  s.device = j.value("device", std::string());
  s.settings = j.value("settings", std::string());
  s.open = j.value("open", false);
  s.counters.frames_sent = j.value("frames_sent", std::uint64_t{0});
  s.counters.frames_received = j.value("frames_received", std::uint64_t{0});
  s.counters.errors = j.value("errors", std::uint64_t{0});
  s.queue = j.value("queue", std::uint64_t{0});
}

namespace {
Labels labels_of(const LineStatus& s) { return {{"line", s.name}, {"role", s.role}}; }
}  // namespace

const std::vector<Statistic<LineStatus>>& line_statistics() {
  using enum MetricType;
  static const std::vector<Statistic<LineStatus>> all{
      {"line_open", gauge, "Whether the RS-485 line's device is open, by line.",
       [](const LineStatus& s, Samples& out) { out.add(s.open, labels_of(s)); }},
      {"line_frames_sent_total", counter, "Frames the bridge sent on the line, by line.",
       [](const LineStatus& s, Samples& out) { out.add(s.counters.frames_sent, labels_of(s)); }},
      {"line_frames_received_total", counter, "Frames with a good CRC received on the line, by line.",
       [](const LineStatus& s, Samples& out) { out.add(s.counters.frames_received, labels_of(s)); }},
      {"line_errors_total", counter,
       "Frames with a bad CRC or length on the line, and a master line's unanswered requests, by line.",
       [](const LineStatus& s, Samples& out) { out.add(s.counters.errors, labels_of(s)); }},
      {"line_queue", gauge, "Requests waiting for the line, by line.",
       [](const LineStatus& s, Samples& out) { out.add(s.queue, labels_of(s)); }},
  };
  return all;
}

}  // namespace unima::status
