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
// - Reads are retried at once, up to `retries` times; writes never (a write that got no
//   answer goes again at its next period, with the value of then).
// - A device that failed `degrade_after` transactions in a row is degraded: its requests
//   stop, and one probe goes every backoff interval (doubling up to backoff_max), placed
//   where it delays no request of a healthy device — unless it has waited a whole interval
//   for such a place. One answer makes the device healthy again. So a dead slave costs the
//   others at most one response time-out per probe interval.

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "modbus/master_plan.hpp"

namespace unima::modbus {

class MasterScheduler {
 public:
  using Clock = std::chrono::steady_clock;
  using TimePoint = Clock::time_point;
  using Duration = Clock::duration;

  struct DeviceTiming {
    Duration min_gap{0};
    Duration response_timeout{std::chrono::milliseconds(500)};
  };

  struct Options {
    unsigned retries = 1;
    unsigned degrade_after = 3;
    Duration backoff{std::chrono::seconds(1)};
    Duration backoff_max{std::chrono::seconds(30)};
    Duration frame_gap{0};
    DeviceTiming default_timing;
  };

  /// A request to send: which, and whether it is a retry or a degraded device's probe.
  struct Choice {
    std::size_t request = 0;
    unsigned attempt = 0;  // 0 first, 1.. retries
    bool probe = false;
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

  const PlannedRequest& request(std::size_t index) const { return slots_[index].request; }
  std::size_t request_count() const { return slots_.size(); }
  bool active(std::size_t index) const { return slots_[index].active; }
  /// Occurrences of the request left out because it was more than a period late.
  std::uint64_t missed(std::size_t index) const { return slots_[index].missed; }
  TimePoint due(std::size_t index) const { return slots_[index].due; }
  bool degraded(std::uint8_t device) const;
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
    unsigned failures = 0;
    bool degraded = false;
    Duration interval{0};
    TimePoint next_probe;
  };

  const Device& device(std::uint8_t address) const { return devices_.at(address); }
  TimePoint device_ready(const Device& d) const;
  std::optional<std::size_t> probe_slot(std::uint8_t address) const;
  void advance(Slot& slot, TimePoint now);

  std::vector<Slot> slots_;
  std::map<std::uint8_t, Device> devices_;
  Options options_;
  std::optional<Choice> retry_;
  TimePoint line_free_;
};

}  // namespace unima::modbus
