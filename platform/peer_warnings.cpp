#include "platform/peer_warnings.hpp"

#include <spdlog/spdlog.h>

#include "platform/log_text.hpp"

namespace unima::platform {

bool PeerWarnings::log(Level level, std::string_view what, std::string_view peer, std::string_view message,
                       Clock::time_point now) {
  report(now);  // a period that ended without the timer (none installed, or late) first
  if (level == Level::info && !info_kinds_.contains(what)) info_kinds_.emplace(what);
  const bool opens = !limiter_.period_end();
  const bool logged = limiter_.admit(what, peer_host(peer), now);
  if (logged) spdlog::log(level == Level::info ? spdlog::level::info : spdlog::level::warn, "{}", log_safe(message));
  if (opens && period_opened_) period_opened_();
  return logged;
}

void PeerWarnings::report(Clock::time_point now) {
  const auto period = std::chrono::duration<double>(limiter_.options().period).count();
  for (const auto& held : limiter_.end_period(now)) {
    const auto level = info_kinds_.contains(held.group) ? spdlog::level::info : spdlog::level::warn;
    if (held.key.empty())
      spdlog::log(level, "{}: {} more from other peers in the last {:g} s (too many peers to tell apart)", held.group,
                  held.count, period);
    else
      spdlog::log(level, "{} from {}: {} more in the last {:g} s", held.group, log_safe(held.key), held.count, period);
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
