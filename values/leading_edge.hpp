#pragma once
// When a change goes north (SPEC §12 for MQTT's bank documents, §13 for the page's live
// values): at most one update every 100 ms, the first at once — a change that comes when
// the last update went out 100 ms ago or more goes now (the leading edge), one that comes
// sooner goes when those 100 ms are up, with the state it has then (never a backlog). So
// a single change after a quiet moment is not held to a fixed grid, and a value that
// changes a thousand times a second still costs ten updates. Pure: time points passed in.

#include <chrono>
#include <optional>

namespace unima::values {

class LeadingEdge {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr std::chrono::milliseconds cap{100};

  /// When a change noticed at `now` may go: `now` itself on the leading edge.
  Clock::time_point when(Clock::time_point now) const { return last_ && now < *last_ + cap ? *last_ + cap : now; }
  /// An update went out at `now`.
  void went(Clock::time_point now) { last_ = now; }

 private:
  std::optional<Clock::time_point> last_;  // none yet: the first change goes at once
};

}  // namespace unima::values
