#include "tls/handshake_limiter.hpp"

#include <algorithm>
#include <iterator>

namespace unima::tls {

const char* HandshakeLimiter::name(Verdict verdict) {
  switch (verdict) {
    case Verdict::admitted: return "admitted";
    case Verdict::host_in_progress: return "per_host_in_progress";
    case Verdict::host_rate: return "per_host_rate";
    case Verdict::all_in_progress: return "in_progress";
  }
  return "?";
}

void HandshakeLimiter::refill(Host& host, Clock::time_point now) const {
  if (now <= host.refilled) return;  // a clock that went back refills nothing
  const double seconds = std::chrono::duration<double>(now - host.refilled).count();
  host.tokens = std::min(limits_.per_host_burst, host.tokens + seconds * limits_.per_host_rate);
  host.refilled = now;
}

void HandshakeLimiter::forget_hosts_at_rest(Clock::time_point now) {
  for (auto at = hosts_.begin(); at != hosts_.end();) {
    refill(at->second, now);
    const bool at_rest = at->second.in_progress == 0 && at->second.tokens >= limits_.per_host_burst;
    at = at_rest ? hosts_.erase(at) : std::next(at);
  }
}

HandshakeLimiter::Verdict HandshakeLimiter::refuse(Verdict verdict) {
  ++counters_.refused[static_cast<std::size_t>(verdict) - 1];
  return verdict;
}

HandshakeLimiter::Verdict HandshakeLimiter::admit(std::string_view host, Clock::time_point now) {
  auto at = hosts_.find(host);
  if (at == hosts_.end()) {
    if (hosts_.size() >= limits_.hosts) forget_hosts_at_rest(now);
    // Every host remembered has handshaken within the last burst/rate seconds: so many
    // hosts at once are a flood of their own, held like one more than `in_progress`.
    if (hosts_.size() >= limits_.hosts) return refuse(Verdict::all_in_progress);
    at = hosts_.emplace(std::string(host), Host{limits_.per_host_burst, now}).first;
  }
  auto& h = at->second;
  refill(h, now);
  if (h.in_progress >= limits_.per_host_in_progress) return refuse(Verdict::host_in_progress);
  if (h.tokens < 1) return refuse(Verdict::host_rate);
  if (in_progress_ >= limits_.in_progress) return refuse(Verdict::all_in_progress);
  h.tokens -= 1;
  ++h.in_progress;
  ++in_progress_;
  return Verdict::admitted;
}

void HandshakeLimiter::finished(std::string_view host, bool completed) {
  ++(completed ? counters_.completed : counters_.failed);
  if (in_progress_ > 0) --in_progress_;
  const auto at = hosts_.find(host);
  // Remembered while in progress (forget_hosts_at_rest keeps it), so always found.
  if (at != hosts_.end() && at->second.in_progress > 0) --at->second.in_progress;
}

}  // namespace unima::tls
