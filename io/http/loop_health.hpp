#pragma once
// Whether the event loop turns (SPEC §13, /healthz): a heartbeat every 250 ms; a beat
// that comes over 2 s late is a stall that just ended, and /healthz says so for a while,
// so that a scraper polling every few seconds sees it. Pure: the time is passed in.

#include <chrono>
#include <optional>
#include <string>

#include <fmt/format.h>

namespace unima::io {

class LoopHealth {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr std::chrono::milliseconds beat_interval{250};
  static constexpr std::chrono::seconds stall_limit{2};
  static constexpr std::chrono::seconds stall_report_window{5};

  void beat(Clock::time_point now) {
    if (const auto gap = now - last_beat_; gap > stall_limit) {
      last_stall_ = std::chrono::duration_cast<std::chrono::milliseconds>(gap);
      stall_reported_until_ = now + stall_report_window;
    }
    last_beat_ = now;
  }

  /// Why the loop counts as stalled at `now`; nullopt while it turns.
  std::optional<std::string> stall(Clock::time_point now) const {
    const auto silent = std::chrono::duration_cast<std::chrono::milliseconds>(now - last_beat_);
    if (silent > stall_limit) return fmt::format("the event loop did not turn for {} ms", silent.count());
    if (now < stall_reported_until_)
      return fmt::format("the event loop did not turn for {} ms a moment ago", last_stall_.count());
    return std::nullopt;
  }

 private:
  Clock::time_point last_beat_ = Clock::now();
  std::chrono::milliseconds last_stall_{0};
  Clock::time_point stall_reported_until_{};
};

}  // namespace unima::io
