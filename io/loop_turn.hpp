#pragma once

// How long one handler may keep the event loop before it lets the others run (issue 43,
// finding 6). Work that comes in bursts — MQTT commands read off the broker's socket,
// their writes committed and answered once a sync made them durable — is done in slices of
// about `loop_turn_budget`, so that a Modbus request arriving meanwhile waits for a few
// slices, not for the burst. No Asio here: the callers post their next slice themselves.

#include <algorithm>
#include <chrono>
#include <cstddef>

namespace unima::io {

/// An idle Modbus read takes 0.1–0.2 ms on loopback, and a burst should add no more than
/// that to it, though a turn of the loop may run a slice of each kind of work (a read of
/// the broker's socket, commands carried out, writes answered, answers sent). One command
/// or answer costs 10–30 µs on amd64: a slice takes at least one, whatever the box.
/// docs/performance.md, "A burst of MQTT commands", measured 25, 50 and 100 µs.
inline constexpr std::chrono::microseconds loop_turn_budget{25};

/// For work whose pieces are checked one by one: `spent()` once the budget since `begin()`
/// is gone.
class TurnDeadline {
 public:
  using Clock = std::chrono::steady_clock;

  void begin(Clock::time_point now = Clock::now()) { began_ = now; }
  bool spent(Clock::time_point now = Clock::now()) const { return now - began_ >= loop_turn_budget; }

 private:
  Clock::time_point began_{};
};

/// For work whose pieces cannot be cut apart once begun (a slice's writes are all committed
/// before any is answered): how many pieces the next slice takes, from what the last one
/// cost. Starts at `most` and never leaves [1, most].
class SliceSize {
 public:
  explicit SliceSize(std::size_t most) : most_(std::max<std::size_t>(most, 1)), next_(most_) {}

  std::size_t next() const { return next_; }
  std::size_t most() const { return most_; }

  /// `done` pieces took `elapsed`: the next slice takes as many as fit the budget at that
  /// pace, growing at most twofold a slice (one slice the scheduler cut short is no pace).
  void took(std::size_t done, std::chrono::nanoseconds elapsed) {
    if (done == 0) return;
    const auto budget = std::chrono::nanoseconds(loop_turn_budget).count();
    const auto per_piece = std::max<std::chrono::nanoseconds::rep>(elapsed.count() / static_cast<long long>(done), 1);
    const auto fits = static_cast<std::size_t>(std::max<long long>(budget / per_piece, 1));
    next_ = std::clamp<std::size_t>(fits, 1, std::min(most_, 2 * std::max(next_, done)));
  }

 private:
  std::size_t most_;
  std::size_t next_;
};

}  // namespace unima::io
