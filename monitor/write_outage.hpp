#pragma once
// When a log file that cannot be written is worth a line in the journal: the first failure
// of an outage, and its end once writing has worked for a while (issue 17, SPEC §10).
//
// Why not every change: on a full disk the appender cuts a failed write back to the last
// whole line, which frees a little room, so the next small write succeeds and the one after
// fails again — hundreds of "cannot write" / "writing again" pairs a second. An outage ends
// only when no write has failed for `settle` and one has succeeded since; the journal then
// says how long it lasted and how many writes failed in it.
//
// Pure: the caller passes the time.

#include <chrono>
#include <cstdint>
#include <optional>

namespace unima::monitor {

class WriteOutage {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr Clock::duration default_settle = std::chrono::seconds(5);

  explicit WriteOutage(Clock::duration settle = default_settle) : settle_(settle) {}

  /// A write failed at `now`. True when it begins an outage: log it.
  bool failed(Clock::time_point now);

  struct Recovery {
    Clock::duration lasted;  // from the first failure to the last
    std::uint64_t failed_writes;
  };
  /// A write succeeded at `now`: the outage's end when it is over, else nullopt (also when
  /// there was none).
  std::optional<Recovery> succeeded(Clock::time_point now);

  bool failing() const { return failing_; }

 private:
  Clock::duration settle_;
  bool failing_ = false;
  Clock::time_point first_failure_{};
  Clock::time_point last_failure_{};
  std::uint64_t failed_writes_ = 0;
};

}  // namespace unima::monitor
