#pragma once
// When the edge node does again what something asked for (SPEC §16): at once when the last
// time is `interval` old or more (the leading edge, so a change after a quiet while goes
// out without waiting), otherwise once it is — one time for all that asked meanwhile.
// Pure: the caller has the clock and the timer.
//
// DataPacing, 10 ms: when the node looks at the banks again after they changed. A look
// publishes a DDATA for each device whose metrics changed, so no device sends more than one
// DDATA per interval: 1,000 telegrams a second into a device make at most 1000 ms ÷
// interval DDATA, the latest values each time (report by exception, as Sparkplug's data
// is; a host wants the state, not every sample). 10 ms is within the 20 ms a change may
// take to a host at p99 with the broker's and the host's share, and 100 DDATA/s per device
// at most, which a broker and Ignition take without a queue. (Rebirths: rebirth_pacing.)

#include <chrono>
#include <cstdint>
#include <optional>

namespace unima::sparkplug {

template <std::int64_t IntervalMs>
class Pacing {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr Clock::duration interval = std::chrono::milliseconds(IntervalMs);

  /// Asked for at `now`: when to do it — `now` (at once) or later; nullopt when it is due
  /// already (the time it was told of takes this request too).
  std::optional<Clock::time_point> changed(Clock::time_point now) {
    if (due_) return std::nullopt;
    due_ = true;
    if (!last_ || now - *last_ >= interval) return now;
    return *last_ + interval;
  }
  /// Done at `now`, for everything asked so far (whatever asked for it: a change, births,
  /// a new connection).
  void looked(Clock::time_point now) {
    last_ = now;
    due_ = false;
  }
  /// What was due could not be done (the broker does not keep up): when to try again.
  Clock::time_point retry(Clock::time_point now) {
    due_ = true;
    return now + interval;
  }

 private:
  std::optional<Clock::time_point> last_;
  bool due_ = false;
};

using DataPacing = Pacing<10>;

}  // namespace unima::sparkplug
