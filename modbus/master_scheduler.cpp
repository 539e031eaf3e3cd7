#include "modbus/master_scheduler.hpp"

#include <algorithm>

namespace unima::modbus {

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

MasterScheduler::Decision MasterScheduler::decide(TimePoint now) const {
  Decision decision;
  if (retry_) {
    const auto ready = device_ready(device(slots_[retry_->request].request.device));
    if (ready <= now) decision.send = *retry_;
    else decision.wake = ready;
    return decision;
  }

  // The healthy devices' requests, earliest due first.
  std::optional<std::size_t> chosen;
  TimePoint next_healthy = TimePoint::max();
  for (std::size_t i = 0; i < slots_.size(); ++i) {
    const auto& s = slots_[i];
    if (!s.active) continue;
    const auto& d = device(s.request.device);
    if (d.degraded) continue;
    const auto ready = std::max(s.due, device_ready(d));
    next_healthy = std::min(next_healthy, ready);
    if (ready <= now && (!chosen || s.due < slots_[*chosen].due)) chosen = i;
  }
  if (chosen) {
    decision.send = Choice{*chosen, 0, false};
    return decision;
  }
  decision.wake = next_healthy;

  // Probes of degraded devices, where they delay no healthy request.
  for (const auto& [address, d] : devices_) {
    if (!d.degraded) continue;
    const auto slot = probe_slot(address);
    if (!slot) continue;
    const auto ready = std::max(d.next_probe, device_ready(d));
    if (ready > now) {
      decision.wake = std::min(decision.wake, ready);
      continue;
    }
    const auto cost = d.timing.response_timeout + options_.frame_gap;
    const bool in_the_way = next_healthy < now + cost;
    const auto patience_end = d.next_probe + d.interval;
    if (in_the_way && now < patience_end) {
      decision.wake = std::min(decision.wake, patience_end);
      continue;
    }
    decision.send = Choice{*slot, 0, true};
    return decision;
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
  retry_.reset();
}

void MasterScheduler::skip(const Choice& choice, TimePoint now) {
  advance(slots_[choice.request], now);
  retry_.reset();
}

MasterScheduler::Transition MasterScheduler::end(const Choice& choice, Outcome outcome, TimePoint now) {
  line_free_ = now + options_.frame_gap;
  const auto& request = slots_[choice.request].request;
  Device& d = devices_.at(request.device);
  if (outcome == Outcome::answered) {
    d.failures = 0;
    if (!d.degraded) return Transition::none;
    d.degraded = false;
    return Transition::recovered;
  }
  ++d.failures;
  if (choice.probe) {
    d.interval = std::min(d.interval * 2, options_.backoff_max);
    d.next_probe = now + d.interval;
    return Transition::none;
  }
  if (!d.degraded && d.failures >= options_.degrade_after) {
    d.degraded = true;
    d.interval = options_.backoff;
    d.next_probe = now + d.interval;
    return Transition::degraded;
  }
  if (request.is_read() && choice.attempt < options_.retries) retry_ = Choice{choice.request, choice.attempt + 1, false};
  return Transition::none;
}

std::size_t MasterScheduler::replace(std::size_t index, std::vector<PlannedRequest> parts) {
  slots_[index].active = false;
  if (retry_ && retry_->request == index) retry_.reset();
  const auto due = slots_[index].due;
  const auto first = slots_.size();
  for (auto& p : parts) slots_.push_back(Slot{std::move(p), due, true, 0});
  return first;
}

bool MasterScheduler::degraded(std::uint8_t address) const {
  const auto it = devices_.find(address);
  return it != devices_.end() && it->second.degraded;
}

MasterScheduler::Duration MasterScheduler::probe_interval(std::uint8_t address) const {
  return device(address).interval;
}

const MasterScheduler::DeviceTiming& MasterScheduler::timing(std::uint8_t address) const {
  return device(address).timing;
}

}  // namespace unima::modbus
