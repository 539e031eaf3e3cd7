#pragma once
// How long the gateway's forwarded requests waited for the line (SPEC §14, docs/gateway.md,
// "Seen and counted"): from the client's request reaching the master to its frame going on
// the line. Kept as the last, the mean and the longest wait, and the sum and count they
// come from (Prometheus' summary), because an integrator asks "how long now, usually, at
// worst" — a histogram's buckets would have to guess the line's speed. Pure: the caller
// measures each wait.

#include <chrono>
#include <cstdint>

namespace unima::master {

class WaitTime {
 public:
  using Duration = std::chrono::steady_clock::duration;

  /// One request took the line after waiting `waited` (a negative wait counts as none).
  void took_line(Duration waited);

  std::uint64_t count() const { return count_; }
  Duration sum() const { return sum_; }
  Duration last() const { return last_; }
  Duration max() const { return max_; }
  /// The mean of every wait so far; zero before the first.
  Duration mean() const { return count_ == 0 ? Duration::zero() : sum_ / static_cast<Duration::rep>(count_); }

 private:
  std::uint64_t count_ = 0;
  Duration sum_{};
  Duration last_{};
  Duration max_{};
};

}  // namespace unima::master
