#pragma once
// The warnings a peer can cause — a bad MBAP header, a malformed feed line, a client that
// stops reading — logged rate-limited per peer host (SPEC §10): the first of a kind from a
// host, then once a minute how many more came (platform/warning_limiter). The whole line
// is escaped (platform/log_text), so nothing in it can forge another line. The info lines
// a peer causes by coming and going (a feed client's connects) are limited the same way,
// and their counts logged at info too: a client that reconnects in a loop cannot flood
// the log either.
//
// One per process, like the log it writes to, so that any adapter warns through it with
// one call; the daemon's timer (io/peer_warning_reports) logs the counts when a period
// ends. Used on the event loop's thread only.

#include <chrono>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>

#include <fmt/format.h>

#include "platform/warning_limiter.hpp"

namespace unima::platform {

class PeerWarnings {
 public:
  using Clock = WarningLimiter::Clock;

  explicit PeerWarnings(WarningLimiter::Options options = {}) : limiter_(options) {}

  /// Logs `message` as a warning when it is the first of `what` (e.g. "modbus tcp: bad
  /// MBAP headers") from the host of `peer` ("address:port") in this period, else counts
  /// it. True when it was logged.
  bool warn(std::string_view what, std::string_view peer, std::string_view message, Clock::time_point now) {
    return log(Level::warning, what, peer, message, now);
  }
  /// The same at info level, for what a well-behaved peer does too (connecting), and
  /// the counts of `what` at info as well.
  bool note(std::string_view what, std::string_view peer, std::string_view message, Clock::time_point now) {
    return log(Level::info, what, peer, message, now);
  }

  /// Logs the counts of the period that ended by `now` (nothing before its end).
  void report(Clock::time_point now);
  /// When report() has something to say; nullopt while nothing is counted.
  std::optional<Clock::time_point> next_report() const { return limiter_.period_end(); }
  /// Called when a period opens: whoever calls report() then knows to wake at its end.
  void on_period_opened(std::function<void()> callback) { period_opened_ = std::move(callback); }

 private:
  enum class Level { info, warning };
  bool log(Level level, std::string_view what, std::string_view peer, std::string_view message, Clock::time_point now);

  WarningLimiter limiter_;
  std::function<void()> period_opened_;
  std::set<std::string, std::less<>> info_kinds_;  // the `what`s noted at info: a few fixed names
};

/// The process's.
PeerWarnings& peer_warnings();

/// The host part of a peer "address:port" ("[v6]:port" or "v6:port" alike); anything
/// else (a unix socket's path) as it is.
std::string_view peer_host(std::string_view peer);

/// peer_warnings().warn() with the message formatted (only fmt's arguments, never text
/// from outside, go in `format`).
template <typename... Args>
bool warn_from_peer(std::string_view what, std::string_view peer, fmt::format_string<Args...> format, Args&&... args) {
  return peer_warnings().warn(what, peer, fmt::format(format, std::forward<Args>(args)...), PeerWarnings::Clock::now());
}

/// peer_warnings().note() with the message formatted, as warn_from_peer.
template <typename... Args>
bool note_from_peer(std::string_view what, std::string_view peer, fmt::format_string<Args...> format, Args&&... args) {
  return peer_warnings().note(what, peer, fmt::format(format, std::forward<Args>(args)...), PeerWarnings::Clock::now());
}

}  // namespace unima::platform
