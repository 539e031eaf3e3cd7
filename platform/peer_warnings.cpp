#include "platform/peer_warnings.hpp"

#include <spdlog/spdlog.h>

#include "platform/log_text.hpp"

namespace unima::platform {

bool PeerWarnings::warn(std::string_view what, std::string_view peer, std::string_view message, Clock::time_point now) {
  report(now);  // a period that ended without the timer (none installed, or late) first
  const bool opens = !limiter_.period_end();
  const bool logged = limiter_.admit(what, peer_host(peer), now);
  if (logged) spdlog::warn("{}", log_safe(message));
  if (opens && period_opened_) period_opened_();
  return logged;
}

void PeerWarnings::report(Clock::time_point now) {
  const auto period = std::chrono::duration<double>(limiter_.options().period).count();
  for (const auto& held : limiter_.end_period(now)) {
    if (held.key.empty())
      spdlog::warn("{}: {} more from other peers in the last {:g} s (too many peers to tell apart)", held.group,
                   held.count, period);
    else
      spdlog::warn("{} from {}: {} more in the last {:g} s", held.group, log_safe(held.key), held.count, period);
  }
}

PeerWarnings& peer_warnings() {
  static PeerWarnings warnings;
  return warnings;
}

std::string_view peer_host(std::string_view peer) {
  const auto colon = peer.rfind(':');
  if (colon == std::string_view::npos || colon + 1 == peer.size()) return peer;
  if (peer.find_first_not_of("0123456789", colon + 1) != std::string_view::npos) return peer;
  auto host = peer.substr(0, colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  return host;
}

}  // namespace unima::platform
