#pragma once
// How many password checks (web/basic_auth) may be computed, and for whom, so that a peer
// guessing passwords costs only itself (issue 29): each peer host has at most one check in
// flight and a token bucket of checks (2 a second, a burst of 5) — beyond either, that host
// is told to wait (429) and nobody else notices; and all hosts together have at most
// `checks` queued or running — beyond that, many hosts guess at once and every new check
// is told to come back (503), so that the queue, and the wait of a login in it, stays short.
//
// Pure: time points are given. Hosts whose bucket is full and that have nothing in flight
// are forgotten when the table is full (they are as new); a table full of busy hosts turns
// new hosts away as `busy`.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>

namespace unima::web {

class LoginLimits {
 public:
  using Clock = std::chrono::steady_clock;

  struct Options {
    unsigned checks_per_host = 1;   // in flight at once
    double host_rate = 2;           // checks a second, per host, on average
    double host_burst = 5;          // and at once after a pause
    unsigned checks = 8;            // queued or running, all hosts together
    std::size_t hosts = 1024;       // remembered at once
  };
  /// What a 429 or 503 asks the client to wait.
  static constexpr std::chrono::seconds retry_after{1};

  enum class Admission : std::uint8_t { admitted, peer_limited, busy };

  LoginLimits() : LoginLimits(Options{}) {}
  explicit LoginLimits(Options options) : options_(options) {}

  /// May `host` start a check at `now`? When admitted, it counts as in flight until release().
  Admission admit(std::string_view host, Clock::time_point now);
  /// The check admitted for `host` is done.
  void release(std::string_view host);

  unsigned in_flight() const { return in_flight_; }
  std::size_t hosts_remembered() const { return hosts_.size(); }
  const Options& options() const { return options_; }

 private:
  struct Host {
    double tokens = 0;
    Clock::time_point refilled{};
    unsigned in_flight = 0;
  };
  void refill(Host& host, Clock::time_point now) const;
  bool make_room(Clock::time_point now);

  Options options_;
  std::unordered_map<std::string, Host> hosts_;
  unsigned in_flight_ = 0;
};

}  // namespace unima::web
