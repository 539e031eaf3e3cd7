#include "web/login_limits.hpp"

#include <algorithm>
#include <iterator>

namespace unima::web {

void LoginLimits::refill(Host& host, Clock::time_point now) const {
  if (now > host.refilled) {
    const std::chrono::duration<double> elapsed = now - host.refilled;
    host.tokens = std::min(options_.host_burst, host.tokens + elapsed.count() * options_.host_rate);
    host.refilled = now;
  }
}

bool LoginLimits::make_room(Clock::time_point now) {
  for (auto it = hosts_.begin(); it != hosts_.end();) {
    refill(it->second, now);
    const bool rested = it->second.in_flight == 0 && it->second.tokens >= options_.host_burst;
    it = rested ? hosts_.erase(it) : std::next(it);
  }
  return hosts_.size() < options_.hosts;
}

LoginLimits::Admission LoginLimits::admit(std::string_view host_name, Clock::time_point now) {
  auto found = hosts_.find(std::string(host_name));
  if (found == hosts_.end()) {
    if (hosts_.size() >= options_.hosts && !make_room(now)) return Admission::busy;
    found = hosts_.emplace(std::string(host_name), Host{options_.host_burst, now, 0}).first;
  }
  auto& host = found->second;
  refill(host, now);
  if (host.in_flight >= options_.checks_per_host || host.tokens < 1) return Admission::peer_limited;
  if (in_flight_ >= options_.checks) return Admission::busy;
  host.tokens -= 1;
  ++host.in_flight;
  ++in_flight_;
  return Admission::admitted;
}

void LoginLimits::release(std::string_view host_name) {
  const auto found = hosts_.find(std::string(host_name));
  if (found == hosts_.end() || found->second.in_flight == 0) return;
  --found->second.in_flight;
  --in_flight_;
}

}  // namespace unima::web
