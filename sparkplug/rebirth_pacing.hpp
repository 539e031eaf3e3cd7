#pragma once
// How often an NCMD `Node Control/Rebirth` is carried out (issue 43, finding 8): every
// birth again is tens of kB out for a few bytes in, so whoever may publish NCMD could turn
// a trickle into a flood (500 requests: 13.9 MB of births). The edge node's pacing
// (data_pacing) with 5 s: at once when the last rebirth is 5 s old or more, otherwise one
// rebirth when it is, for every request that came meanwhile (the host that asked still
// gets its births, a few seconds later); those requests are counted. Pure.

#include <cstdint>

#include "sparkplug/data_pacing.hpp"

namespace unima::sparkplug {

class RebirthPacing {
 public:
  using Clock = Pacing<5000>::Clock;
  static constexpr Clock::duration min_interval = Pacing<5000>::interval;

  enum class Verdict {
    now,     // rebirth now (done() is implied)
    later,   // one rebirth at due_at(): the caller sets its timer, then calls done()
    joined,  // a rebirth is due already and takes this request too
  };
  Verdict asked(Clock::time_point now) {
    const auto when = pacing_.changed(now);
    if (when && *when <= now) {
      pacing_.looked(now);
      return Verdict::now;
    }
    ++coalesced_;
    if (!when) return Verdict::joined;
    due_at_ = *when;
    return Verdict::later;
  }
  Clock::time_point due_at() const { return due_at_; }
  /// The deferred rebirth went out at `now`.
  void done(Clock::time_point now) { pacing_.looked(now); }
  /// Requests that were not a rebirth of their own (later and joined).
  std::uint64_t coalesced() const { return coalesced_; }

 private:
  Pacing<5000> pacing_;
  Clock::time_point due_at_{};
  std::uint64_t coalesced_ = 0;
};

}  // namespace unima::sparkplug
