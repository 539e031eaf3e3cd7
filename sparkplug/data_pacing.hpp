#pragma once
// When the edge node looks at the banks again after they changed (SPEC §16, issue 33's
// performance): at once when the last look is `interval` old or more (the leading edge, so
// a change after a quiet while goes out as DDATA without waiting), otherwise once it is —
// one look for all that changed meanwhile. A look publishes a DDATA for each device whose
// metrics changed, so no device sends more than one DDATA per interval: 1,000 telegrams a
// second into a device make at most 1000 ms ÷ interval DDATA, the latest values each time
// (report by exception, as Sparkplug's data is; a host wants the state, not every sample).
//
// 10 ms: within the 20 ms a change may take to a host at p99 with the broker's and the
// host's share, and 100 DDATA/s per device at most, which a broker and Ignition take
// without a queue. Pure: the caller has the clock and the timer.

#include <chrono>
#include <optional>

namespace unima::sparkplug {

class DataPacing {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr Clock::duration interval = std::chrono::milliseconds(10);

  /// The banks changed at `now`: when to look — `now` (at once) or later; nullopt when a
  /// look is due already (the one it was told of takes this change too).
  std::optional<Clock::time_point> changed(Clock::time_point now);
  /// A look at `now` took every change so far (whatever asked for it: a change, births, a
  /// new connection).
  void looked(Clock::time_point now);
  /// A look that was due could not publish (the broker does not keep up): when to try again.
  Clock::time_point retry(Clock::time_point now);

 private:
  std::optional<Clock::time_point> last_look_;
  bool due_ = false;
};

}  // namespace unima::sparkplug
