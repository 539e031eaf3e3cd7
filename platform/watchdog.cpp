#include "platform/watchdog.hpp"

#include <systemd/sd-daemon.h>

#include <cstdint>

#include <spdlog/spdlog.h>

namespace unima::platform {

void Watchdog::start() {
  std::uint64_t usec = 0;
  if (sd_watchdog_enabled(0, &usec) <= 0 || usec == 0) return;
  // Half the time-out, as sd_watchdog_enabled(3) advises: one late turn of the loop is not a hang.
  interval_ = std::chrono::microseconds(usec / 2);
  spdlog::info("watchdog: keep-alive every {} ms", std::chrono::duration_cast<std::chrono::milliseconds>(interval_).count());
  sd_notify(0, "WATCHDOG=1");
  schedule();
}

void Watchdog::stop() {
  timer_.cancel();
  interval_ = std::chrono::microseconds(0);
}

void Watchdog::schedule() {
  timer_.expires_after(interval_);
  timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec || interval_.count() == 0) return;
    sd_notify(0, "WATCHDOG=1");
    schedule();
  });
}

}  // namespace unima::platform
