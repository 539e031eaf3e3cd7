#pragma once
// How often an NCMD `Node Control/Rebirth` is carried out (issue 43, finding 8): every
// birth again is tens of kB out for a few bytes in, so whoever may publish NCMD could turn
// a trickle into a flood (500 requests: 13.9 MB of births). At once when the last rebirth
// is 5 s old or more (the leading edge), otherwise one rebirth when it is, for every
// request that came meanwhile (the host that asked still gets its births, a few seconds
// later); those requests are counted. Pure: the caller has the clock and the timer.

#include <chrono>
#include <cstdint>
#include <optional>

namespace unima::sparkplug {

class RebirthPacing {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr Clock::duration min_interval = std::chrono::seconds(5);

  enum class Verdict {
    now,     // rebirth now (done() is implied)
    later,   // one rebirth at due_at(): the caller sets its timer, then calls done()
    joined,  // a rebirth is due already and takes this request too
  };
  Verdict asked(Clock::time_point now) {
    if (deferred_) {
      ++coalesced_;
      return Verdict::joined;
    }
    if (!last_ || now - *last_ >= min_interval) {
      last_ = now;
      return Verdict::now;
    }
    deferred_ = true;
    due_at_ = *last_ + min_interval;
    ++coalesced_;
    return Verdict::later;
  }
  Clock::time_point due_at() const { return due_at_; }
  /// The deferred rebirth went out at `now` (or was cancelled: none stays due).
  void done(Clock::time_point now) {
    last_ = now;
    deferred_ = false;
  }
  /// Requests that were not a rebirth of their own (later and joined).
  std::uint64_t coalesced() const { return coalesced_; }

 private:
  std::optional<Clock::time_point> last_;
  bool deferred_ = false;
  Clock::time_point due_at_{};
  std::uint64_t coalesced_ = 0;
};

}  // namespace unima::sparkplug
