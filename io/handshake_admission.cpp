#include "io/handshake_admission.hpp"

#include <chrono>

#include <fmt/format.h>

#include "platform/peer_warnings.hpp"

namespace unima::io {

std::optional<tls::HandshakeSlot> admit_handshake(const std::shared_ptr<tls::HandshakeLimiter>& limiter,
                                                  const asio::ip::address& address, const std::string& peer,
                                                  std::string_view port_name) {
  using Verdict = tls::HandshakeLimiter::Verdict;
  const auto host = address.to_string();
  const auto verdict = limiter->admit(host, std::chrono::steady_clock::now());
  if (verdict == Verdict::admitted) return tls::HandshakeSlot(limiter, host);
  const auto& limits = limiter->limits();
  const auto what = fmt::format("{}: TLS handshakes refused", port_name);
  if (verdict == Verdict::host_in_progress)
    platform::warn_from_peer(what, peer, "{}: {} has {} TLS handshakes in progress, the most a host may; closing its new connections",
                             port_name, host, limits.per_host_in_progress);
  else if (verdict == Verdict::host_rate)
    platform::warn_from_peer(what, peer, "{}: {} starts TLS handshakes faster than {} a second (at most {} at once); closing its new connections",
                             port_name, host, limits.per_host_rate, limits.per_host_burst);
  else
    platform::warn_from_peer(what, peer, "{}: {} TLS handshakes in progress, the most the port takes; closing a new connection from {}",
                             port_name, limiter->in_progress(), host);
  return std::nullopt;
}

status::HandshakeStatus handshake_counters(const tls::HandshakeLimiter& limiter) {
  using Verdict = tls::HandshakeLimiter::Verdict;
  const auto& c = limiter.counters();
  status::HandshakeStatus s{c.completed, c.failed, limiter.in_progress(), {}};
  for (const auto verdict : {Verdict::host_in_progress, Verdict::host_rate, Verdict::all_in_progress})
    s.refused[tls::HandshakeLimiter::name(verdict)] = c.refused_of(verdict);
  return s;
}

}  // namespace unima::io
