#include "io/monitor_service.hpp"

#include "io/activity.hpp"
#include "monitor/monitor_line.hpp"
#include "platform/utc_time.hpp"

namespace unima::io {

void MonitorService::stage(const Banks& next) {
  if (!monitor::Monitor::same_log(runtime_.config().monitor, next.config.monitor))
    writer_ = monitor::Monitor::make_writer(next.config.monitor);
}

void MonitorService::commit(const Banks&) { runtime_.monitor->reconfigure(runtime_.config().monitor, std::move(writer_)); }

void MonitorService::describe(nlohmann::json& status) const {
  const auto& monitor = *runtime_.monitor;
  status["modbus"] = activity(age<std::chrono::system_clock>(monitor.last_frame_sent()), monitor.frames_sent(), modbus_led_lit);

  status["indicators"] = nlohmann::json::array();
  const auto& indicators = monitor.indicators();
  for (std::size_t i = 0; i < indicators.size(); ++i) {
    nlohmann::json j;
    j["address"] = indicators.spec(i).address;
    j["register"] = indicators.spec(i).reg;
    if (const auto& reading = indicators.reading(i)) {
      std::string time;
      platform::append_utc_time(time, reading->time);
      j["value"] = reading->value;
      j["access"] = reading->access == modbus::CaptureAccess::write ? "write" : "read";
      j["time"] = time;
    } else {
      j["value"] = nullptr;
      j["access"] = nullptr;
      j["time"] = nullptr;
    }
    status["indicators"].push_back(j);
  }

  const auto& m = monitor.config();
  nlohmann::json j;
  j["file"] = m.file.empty() ? nlohmann::json(nullptr) : nlohmann::json(m.file);
  j["stdout"] = m.to_stdout;
  j["format"] = m.format == monitor::MonitorFormat::json ? "json" : "text";
  j["filter"] = monitor.filter().describe();
  j["queue"] = m.queue;
  j["written"] = monitor.written();
  j["dropped"] = monitor.dropped();
  status["monitor"] = j;
}

}  // namespace unima::io
