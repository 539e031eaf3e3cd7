#pragma once
// When the master sends what (SPEC §4, issue #6): the decisions only, from time points the
// caller passes in — no clock, no timers, no I/O, so that every rule is unit-tested.
//
// - Periods without drift: occurrence k of a request is due at start + k·period, whenever
//   occurrence k−1 went out; an occurrence more than a period late is skipped, not bunched.
// - One frame at a time on the line, with `frame_gap` of silence after each transaction
//   (t3.5 on RTU), and per device at least `min_gap` between the starts of two frames
//   (SIC184: ≤100 frames/s; the stepper driver: ≥35 ms per reply).
// - Earliest due first among the requests that may go now.
// - A device is *live* once it has answered and as long as its last transaction was
//   answered. A frame to a device in doubt — a retry, a try after a failure, the probe of a
//   degraded device — goes only where the line is free for its frame and its whole wait for
//   an answer before the next request of a live device falls due ("fits in the gap"). When
//   the gap is shorter than the response time-out but at least half of it (and a quarter
//   longer than the device's slowest answer so far), the frame goes with the wait cut to
//   the gap: a slave that is back answers in its usual time, not at the end of its time-out.
// - Reads are retried up to `retries` times, as soon as a retry fits; a retry that has not
//   fitted by its request's next occurrence gives way to it. Writes are never retried (a
//   write that got no answer goes again at its next period, with the value of then).
// - A device that failed `degrade_after` transactions in a row is degraded: its requests
//   stop, and one probe goes every backoff interval (doubling up to backoff_max). A frame
//   in doubt that found no gap for one backoff interval (a probe: one probe interval) goes
//   anyway, with the whole time-out: a dead slave is never starved of its recovery.
//   One answer makes the device live again; it resumes its grid without a burst.
// - After a time-out the line stays quiet for as long again as the wait that ended, at
//   most `longest_quiet` (timed_out): a slave later than its time-out answers into
//   silence, and the link discards what came before the next frame, so that a late answer
//   is never taken for the next request's (issue 43: a 420 ms slave behind a 300 ms
//   time-out). The bound keeps a long time-out from holding the line twice as long.
// - The first transaction of a device that fails (nobody could know the slave was dead)
//   moves the live devices' schedule past it, by whole multiples of the periods' greatest
//   common divisor so that the phases keep their distances: one longer first interval
//   instead of late frames followed by early ones.

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "master/master_plan.hpp"

namespace unima::master {

class MasterScheduler {
 public:
  using Clock = std::chrono::steady_clock;
  using TimePoint = Clock::time_point;
  using Duration = Clock::duration;

  struct DeviceTiming {
    Duration min_gap{0};
    Duration response_timeout{std::chrono::milliseconds(500)};
    bool operator==(const DeviceTiming&) const = default;
  };

  struct Options {
    unsigned retries = 1;
    unsigned degrade_after = 3;
    Duration backoff{std::chrono::seconds(1)};
    Duration backoff_max{std::chrono::seconds(30)};
    Duration frame_gap{0};
    /// One character on the RTU line (0 on TCP): a request holds the line for its frame
    /// before the wait for the answer begins.
    Duration char_time{0};
    /// Kept free before a live request after a frame in doubt: the timers' and the
    /// adapter's lateness.
    Duration guard{std::chrono::milliseconds(2)};
    DeviceTiming default_timing;
    bool operator==(const Options&) const = default;
  };

  /// A request to send: which, whether it is a retry or a degraded device's probe, and how
  /// long to wait for the answer.
  struct Choice {
    std::size_t request = 0;
    unsigned attempt = 0;  // 0 first, 1.. retries
    bool probe = false;
    Duration timeout{0};   // 0: the device's response_timeout
  };
  struct Decision {
    std::optional<Choice> send;
    TimePoint wake = TimePoint::max();  // when nothing is sent: when to decide again
  };
  enum class Outcome : std::uint8_t {
    answered,  // the slave answered (a value, an exception, even a wrong one): it is alive
    failed,    // no usable answer: time-out, bad CRC, garbage
  };
  enum class Transition : std::uint8_t { none, degraded, recovered };

  MasterScheduler(std::vector<PlannedRequest> requests, const Options& options,
                  std::map<std::uint8_t, DeviceTiming> devices, TimePoint start);

  /// What to send at `now`. Asked only while no transaction is under way.
  Decision decide(TimePoint now) const;
  /// The chosen request went out at `now`.
  void begin(const Choice& choice, TimePoint now);
  /// The chosen request is left out this time (a send whose source is not measured).
  void skip(const Choice& choice, TimePoint now);
  /// The transaction of `choice` ended at `now`.
  Transition end(const Choice& choice, Outcome outcome, TimePoint now);
  /// Replaces request `index` by `parts` (after exception 02); they take over its schedule.
  /// Returns the index of the first part.
  std::size_t replace(std::size_t index, std::vector<PlannedRequest> parts);

  /// When a frame to `unit` may go: the line free after its gap, and the device's min_gap
  /// since its last frame when it is one the master polls (SPEC §14: forwarded requests
  /// keep the same pacing).
  TimePoint ready_for(std::uint8_t unit) const;
  /// A transaction that is not the scheduler's (a forwarded one) held the line from
  /// `start` to `end`.
  void line_used(std::uint8_t unit, TimePoint start, TimePoint end);
  static constexpr Duration longest_quiet = std::chrono::milliseconds(500);
  /// A transaction, the scheduler's or a forwarded one, got no answer within `waited`,
  /// ending at `now`: the line is quiet until now + min(waited, longest_quiet) (at the least).
  void timed_out(TimePoint now, Duration waited);
  /// The line's device was lost and is back (a USB adapter plugged in again): every
  /// degraded device is probed from `now`, its backoff starting again, instead of after
  /// the long interval its probes on the lost line have reached.
  void line_back(TimePoint now);
  /// Whether `unit` is a device the master polls (its profile's timing applies).
  bool knows(std::uint8_t unit) const { return devices_.contains(unit); }

  const PlannedRequest& request(std::size_t index) const { return slots_[index].request; }
  std::size_t request_count() const { return slots_.size(); }
  bool active(std::size_t index) const { return slots_[index].active; }
  /// Occurrences of the request left out because it was more than a period late.
  std::uint64_t missed(std::size_t index) const { return slots_[index].missed; }
  TimePoint due(std::size_t index) const { return slots_[index].due; }
  bool degraded(std::uint8_t device) const;
  /// Answered, and its last transaction was answered: its requests have the line first.
  bool live(std::uint8_t device) const;
  Duration probe_interval(std::uint8_t device) const;
  const DeviceTiming& timing(std::uint8_t device) const;

 private:
  struct Slot {
    PlannedRequest request;
    TimePoint due;
    bool active = true;
    std::uint64_t missed = 0;
  };
  struct Device {
    DeviceTiming timing;
    std::optional<TimePoint> last_start;
    bool contacted = false;  // a transaction of it has ended
    bool heard = false;      // it has answered
    unsigned failures = 0;
    bool degraded = false;
    Duration interval{0};
    TimePoint next_probe;
    Duration slowest{0};     // the longest answered transaction
    bool live() const { return heard && failures == 0 && !degraded; }
    bool in_doubt() const { return failures > 0 || degraded; }
  };

  const Device& device(std::uint8_t address) const { return devices_.at(address); }
  TimePoint device_ready(const Device& d) const;
  TimePoint next_live_request() const;
  std::optional<Duration> fitting_wait(const PlannedRequest& request, const Device& d, TimePoint now,
                                       TimePoint room_end) const;
  std::optional<std::size_t> probe_slot(std::uint8_t address) const;
  std::optional<std::size_t> earliest_due(std::uint8_t address) const;
  void advance(Slot& slot, TimePoint now);
  void resume_grid(std::uint8_t address, TimePoint now);
  void move_live_schedule(TimePoint past);

  std::vector<Slot> slots_;
  std::map<std::uint8_t, Device> devices_;
  Options options_;
  std::optional<Choice> retry_;
  TimePoint line_free_;
};

}  // namespace unima::master
