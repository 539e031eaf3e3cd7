#include "master/master_scheduler.hpp"

#include <algorithm>
#include <numeric>

namespace unima::master {

MasterScheduler::MasterScheduler(std::vector<PlannedRequest> requests, const Options& options,
                                 std::map<std::uint8_t, DeviceTiming> devices, TimePoint start)
    : options_(options), line_free_(start) {
  for (auto& r : requests) {
    Device& d = devices_[r.device];
    const auto given = devices.find(r.device);
    d.timing = given != devices.end() ? given->second : options.default_timing;
    const auto first = start + r.phase;
    slots_.push_back(Slot{std::move(r), first, true, 0});
  }
}

MasterScheduler::TimePoint MasterScheduler::device_ready(const Device& d) const {
  const auto after_gap = d.last_start ? *d.last_start + d.timing.min_gap : line_free_;
  return std::max(line_free_, after_gap);
}

MasterScheduler::TimePoint MasterScheduler::next_live_request() const {
  auto next = TimePoint::max();
  for (const auto& s : slots_) {
    if (!s.active) continue;
    const auto& d = device(s.request.device);
    if (d.live()) next = std::min(next, std::max(s.due, device_ready(d)));
  }
  return next;
}

// How long a frame in doubt may wait for its answer if it goes at `now`: the whole time-out
// when the line has room for it before `room_end`, else the room there is when that is at
// least half the time-out and longer than the device's slowest answer; else it does not fit.
std::optional<MasterScheduler::Duration> MasterScheduler::fitting_wait(const PlannedRequest& request, const Device& d,
                                                                       TimePoint now, TimePoint room_end) const {
  const auto full = d.timing.response_timeout;
  if (room_end == TimePoint::max()) return full;
  const auto frame = options_.char_time * static_cast<long>(rtu_request_size(request));
  const Duration room = std::chrono::floor<std::chrono::milliseconds>(room_end - now - frame - options_.frame_gap -
                                                                      options_.guard);
  if (room >= full) return full;
  const auto shortest = std::min(full, std::max(full / 2, d.slowest + d.slowest / 4));
  if (room >= shortest && room > Duration::zero()) return room;
  return std::nullopt;
}

std::optional<std::size_t> MasterScheduler::probe_slot(std::uint8_t address) const {
  std::optional<std::size_t> best;
  for (std::size_t i = 0; i < slots_.size(); ++i) {
    const auto& s = slots_[i];
    if (!s.active || s.request.device != address) continue;
    if (!best) {
      best = i;
      continue;
    }
    // A read tells as much and changes nothing on the device: prefer it.
    const auto& b = slots_[*best];
    if (std::make_pair(!s.request.is_read(), s.due) < std::make_pair(!b.request.is_read(), b.due)) best = i;
  }
  return best;
}

std::optional<std::size_t> MasterScheduler::earliest_due(std::uint8_t address) const {
  std::optional<std::size_t> best;
  for (std::size_t i = 0; i < slots_.size(); ++i) {
    const auto& s = slots_[i];
    if (s.active && s.request.device == address && (!best || s.due < slots_[*best].due)) best = i;
  }
  return best;
}

MasterScheduler::Decision MasterScheduler::decide(TimePoint now) const {
  Decision decision;
  const auto room_end = next_live_request();

  // A retry, as soon as it fits; once its request's next occurrence is due, that goes instead.
  if (retry_ && slots_[retry_->request].active && slots_[retry_->request].due > now) {
    const auto& slot = slots_[retry_->request];
    const auto& d = device(slot.request.device);
    const auto ready = device_ready(d);
    if (ready > now) {
      decision.wake = ready;
    } else if (const auto wait = fitting_wait(slot.request, d, now, room_end)) {
      decision.send = Choice{retry_->request, retry_->attempt, false, *wait};
      return decision;
    }
  }

  // The requests of devices not in doubt, earliest due first.
  std::optional<std::size_t> chosen;
  TimePoint next_sure = TimePoint::max();
  for (std::size_t i = 0; i < slots_.size(); ++i) {
    const auto& s = slots_[i];
    if (!s.active) continue;
    const auto& d = device(s.request.device);
    if (d.in_doubt()) continue;
    const auto ready = std::max(s.due, device_ready(d));
    next_sure = std::min(next_sure, ready);
    if (ready <= now && (!chosen || s.due < slots_[*chosen].due)) chosen = i;
  }
  if (chosen) {
    decision.send = Choice{*chosen, 0, false, device(slots_[*chosen].request.device).timing.response_timeout};
    return decision;
  }
  decision.wake = std::min(decision.wake, next_sure);

  // Frames to devices in doubt, earliest first, where they fit; or once they have waited
  // their patience out.
  struct Candidate {
    TimePoint due;
    TimePoint patience_end;
    std::size_t slot;
    bool probe;
  };
  std::vector<Candidate> candidates;
  for (const auto& [address, d] : devices_) {
    if (!d.in_doubt()) continue;
    if (d.degraded) {
      if (const auto slot = probe_slot(address)) candidates.push_back({d.next_probe, d.next_probe + d.interval, *slot, true});
    } else if (const auto slot = earliest_due(address)) {
      const auto due = slots_[*slot].due;
      candidates.push_back({due, due + options_.backoff, *slot, false});
    }
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& a, const Candidate& b) { return a.due < b.due; });
  for (const auto& c : candidates) {
    const auto& request = slots_[c.slot].request;
    const auto& d = device(request.device);
    const auto ready = std::max(c.due, device_ready(d));
    if (ready > now) {
      decision.wake = std::min(decision.wake, ready);
      continue;
    }
    auto wait = fitting_wait(request, d, now, room_end);
    if (!wait && now >= c.patience_end) wait = d.timing.response_timeout;
    if (wait) {
      decision.send = Choice{c.slot, 0, c.probe, *wait};
      return decision;
    }
    decision.wake = std::min(decision.wake, c.patience_end);
  }
  return decision;
}

void MasterScheduler::advance(Slot& slot, TimePoint now) {
  slot.due += slot.request.period;
  while (slot.due <= now) {
    slot.due += slot.request.period;
    ++slot.missed;
  }
}

void MasterScheduler::begin(const Choice& choice, TimePoint now) {
  auto& slot = slots_[choice.request];
  devices_.at(slot.request.device).last_start = now;
  if (choice.attempt == 0) advance(slot, now);
  if (retry_ && retry_->request == choice.request) retry_.reset();
}

void MasterScheduler::skip(const Choice& choice, TimePoint now) {
  advance(slots_[choice.request], now);
  if (retry_ && retry_->request == choice.request) retry_.reset();
}

// Occurrences that fell due while the device was in doubt are not made up in a burst.
void MasterScheduler::resume_grid(std::uint8_t address, TimePoint now) {
  for (auto& s : slots_) {
    if (!s.active || s.request.device != address) continue;
    while (s.due < now) {
      s.due += s.request.period;
      ++s.missed;
    }
  }
}

// The live devices' requests move later until none of them falls due before `past`, by a
// multiple of the greatest common divisor of all periods: any two requests meet only at
// multiples of the divisor of their two periods, so their distances stay as phased.
void MasterScheduler::move_live_schedule(TimePoint past) {
  std::chrono::milliseconds::rep divisor = 0;
  auto earliest = TimePoint::max();
  for (const auto& s : slots_) {
    if (!s.active) continue;
    divisor = std::gcd(divisor, s.request.period.count());
    if (device(s.request.device).live()) earliest = std::min(earliest, s.due);
  }
  if (earliest >= past || divisor <= 0) return;
  const Duration step = std::chrono::milliseconds(divisor);
  const auto steps = (past - earliest + step - Duration(1)) / step;
  for (auto& s : slots_)
    if (s.active && device(s.request.device).live()) s.due += steps * step;
}

MasterScheduler::Transition MasterScheduler::end(const Choice& choice, Outcome outcome, TimePoint now) {
  line_free_ = now + options_.frame_gap;
  const auto& request = slots_[choice.request].request;
  const auto address = request.device;
  Device& d = devices_.at(address);
  const bool first_contact = !d.contacted;
  d.contacted = true;
  if (outcome == Outcome::answered) {
    if (d.last_start) d.slowest = std::max(d.slowest, now - *d.last_start);
    d.heard = true;
    const bool was_in_doubt = d.in_doubt();
    const bool was_degraded = d.degraded;
    d.failures = 0;
    d.degraded = false;
    if (was_in_doubt) resume_grid(address, now);
    return was_degraded ? Transition::recovered : Transition::none;
  }
  ++d.failures;
  if (first_contact) move_live_schedule(line_free_);
  if (choice.probe) {
    d.interval = std::min(d.interval * 2, options_.backoff_max);
    d.next_probe = now + d.interval;
    return Transition::none;
  }
  if (!d.degraded && d.failures >= options_.degrade_after) {
    d.degraded = true;
    d.interval = options_.backoff;
    d.next_probe = now + d.interval;
    if (retry_ && slots_[retry_->request].request.device == address) retry_.reset();
    return Transition::degraded;
  }
  if (request.is_read() && choice.attempt < options_.retries) retry_ = Choice{choice.request, choice.attempt + 1, false};
  return Transition::none;
}

void MasterScheduler::line_back(TimePoint now) {
  for (auto& [address, d] : devices_) {
    if (!d.degraded) continue;
    d.interval = options_.backoff;
    d.next_probe = now;
  }
}

std::size_t MasterScheduler::replace(std::size_t index, std::vector<PlannedRequest> parts) {
  slots_[index].active = false;
  if (retry_ && retry_->request == index) retry_.reset();
  const auto due = slots_[index].due;
  const auto first = slots_.size();
  for (auto& p : parts) slots_.push_back(Slot{std::move(p), due, true, 0});
  return first;
}

MasterScheduler::TimePoint MasterScheduler::ready_for(std::uint8_t unit) const {
  const auto it = devices_.find(unit);
  return it == devices_.end() ? line_free_ : device_ready(it->second);
}

void MasterScheduler::timed_out(TimePoint now, Duration waited) {
  line_free_ = std::max(line_free_, now + std::min(waited, longest_quiet));
}

void MasterScheduler::line_used(std::uint8_t unit, TimePoint start, TimePoint end) {
  line_free_ = end + options_.frame_gap;
  if (const auto it = devices_.find(unit); it != devices_.end()) it->second.last_start = start;
}

bool MasterScheduler::degraded(std::uint8_t address) const {
  const auto it = devices_.find(address);
  return it != devices_.end() && it->second.degraded;
}

bool MasterScheduler::live(std::uint8_t address) const {
  const auto it = devices_.find(address);
  return it != devices_.end() && it->second.live();
}

MasterScheduler::Duration MasterScheduler::probe_interval(std::uint8_t address) const {
  return device(address).interval;
}

const MasterScheduler::DeviceTiming& MasterScheduler::timing(std::uint8_t address) const {
  return device(address).timing;
}

}  // namespace unima::master
