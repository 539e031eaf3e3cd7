#pragma once
// systemd's service watchdog (WatchdogSec=): keep-alives sent from the event loop itself,
// so that a loop that stops turning stops them and systemd restarts the daemon.

#include <chrono>

#include "platform/asio.hpp"

namespace unima::platform {

class Watchdog {
 public:
  explicit Watchdog(asio::io_context& io) : timer_(io) {}

  /// Sends WATCHDOG=1 every half of the interval systemd asked for (sd_watchdog_enabled(3));
  /// does nothing when the service has no watchdog.
  void start();
  void stop();
  /// Zero when not running.
  std::chrono::microseconds keep_alive_interval() const { return interval_; }

 private:
  void schedule();

  asio::steady_timer timer_;
  std::chrono::microseconds interval_{0};
};

}  // namespace unima::platform
