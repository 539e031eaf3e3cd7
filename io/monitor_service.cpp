#include "io/monitor_service.hpp"

#include "io/activity.hpp"
#include "monitor/monitor_line.hpp"
#include "monitor/monitor_status.hpp"
#include "platform/utc_time.hpp"
#include "status/activity.hpp"

namespace unima::io {

void MonitorService::stage(const Banks& next) {
  if (!monitor::Monitor::same_log(runtime_.config().monitor, next.config.monitor))
    writer_ = monitor::Monitor::make_writer(next.config.monitor);
}

void MonitorService::commit(const Banks&) { runtime_.monitor->reconfigure(runtime_.config().monitor, std::move(writer_)); }

void MonitorService::describe(status::Document& status) const {
  const auto& monitor = *runtime_.monitor;
  status.modbus =
      status::activity(age<std::chrono::system_clock>(monitor.last_frame_sent()), monitor.frames_sent(), modbus_led_lit);

  std::vector<monitor::IndicatorStatus> indicators;
  const auto& watched = monitor.indicators();
  for (std::size_t i = 0; i < watched.size(); ++i) {
    auto& indicator = indicators.emplace_back(monitor::IndicatorStatus{watched.spec(i).address, watched.spec(i).reg, {}, {}, {}});
    if (const auto& reading = watched.reading(i)) {
      std::string time;
      platform::append_utc_time(time, reading->time);
      indicator.value = reading->value;
      indicator.access = reading->access == modbus::CaptureAccess::write ? "write" : "read";
      indicator.time = time;
    }
  }
  status.indicators = std::move(indicators);

  const auto& m = monitor.config();
  status.monitor = monitor::MonitorStatus{m.file.empty() ? std::nullopt : std::optional(m.file),
                                             m.to_stdout,
                                             m.format == monitor::MonitorFormat::json ? "json" : "text",
                                             monitor.filter().describe(),
                                             m.queue,
                                             monitor.written(),
                                             monitor.dropped()};
}

}  // namespace unima::io
