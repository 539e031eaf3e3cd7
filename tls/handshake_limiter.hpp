#pragma once
// How many TLS handshakes a peer may cost the daemon (SPEC §11, issue 29 row 3). A full
// handshake is the dearest thing a client can ask of the port — an ECDHE key pair and a
// signature, about 0.7–2.5 ms of CPU (computed on the port's worker thread, io/cpu_worker,
// not the loop that serves every Modbus client, but on the same two cores) — and a
// ClientHello costs its sender nothing to replay. So, per peer host: at most `per_host_in_progress`
// handshakes at once and a token bucket (`per_host_rate` a second, `per_host_burst` at
// once); and for all hosts together at most `in_progress` handshakes at once. A
// connection over a limit is closed at accept, before OpenSSL has seen a byte of it.
//
// The limits are constants, not config (docs/security.md): a Modbus master opens one or a
// few connections and keeps them for hours, so a real client never meets them, and a
// value an integrator could get wrong would only weaken them.
//
// Pure: the caller passes the time. Used on the event loop's thread only.

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>

namespace unima::tls {

class HandshakeLimiter {
 public:
  using Clock = std::chrono::steady_clock;

  struct Limits {
    unsigned per_host_in_progress = 2;
    double per_host_rate = 10;   // handshakes a second, refilled continuously
    double per_host_burst = 20;  // the bucket's size: what a host may start at once after a rest
    unsigned in_progress = 64;   // all hosts together
    // Hosts remembered at once: one that is at rest (a full bucket, nothing in progress)
    // is forgotten when room is needed, since it is the same as one never seen.
    std::size_t hosts = 1024;
  };

  /// Why a handshake may not start; `admitted` when it may.
  enum class Verdict { admitted, host_in_progress, host_rate, all_in_progress };
  static constexpr std::size_t refusal_kinds = 3;
  /// "per_host_in_progress", "per_host_rate", "in_progress": the metrics' label.
  static const char* name(Verdict verdict);

  struct Counters {
    std::uint64_t completed = 0;
    std::uint64_t failed = 0;  // started and never completed: an error, a deadline, the client left
    std::uint64_t refused[refusal_kinds] = {};
    std::uint64_t refused_of(Verdict verdict) const { return refused[static_cast<std::size_t>(verdict) - 1]; }
  };

  HandshakeLimiter() : HandshakeLimiter(Limits{}) {}
  explicit HandshakeLimiter(Limits limits) : limits_(limits) {}

  /// A new connection from `host` at `now`: admitted (it takes one of the host's tokens and
  /// a place in progress, until finished()) or refused, and counted either way.
  Verdict admit(std::string_view host, Clock::time_point now);
  /// The end of a handshake admit() let start: completed, or not.
  void finished(std::string_view host, bool completed);

  unsigned in_progress() const { return in_progress_; }
  const Counters& counters() const { return counters_; }
  const Limits& limits() const { return limits_; }
  std::size_t hosts_remembered() const { return hosts_.size(); }

 private:
  struct Host {
    double tokens;
    Clock::time_point refilled;
    unsigned in_progress = 0;
  };
  void refill(Host& host, Clock::time_point now) const;
  void forget_hosts_at_rest(Clock::time_point now);
  Verdict refuse(Verdict verdict);

  Limits limits_;
  std::map<std::string, Host, std::less<>> hosts_;
  unsigned in_progress_ = 0;
  Counters counters_;
};

/// A handshake admitted by a limiter, held by its connection: completed() when it is,
/// else its end counts as a failed handshake. Keeps the limiter alive, so a connection may
/// outlive the port that made it (a reload that moves the port).
class HandshakeSlot {
 public:
  HandshakeSlot() = default;
  HandshakeSlot(std::shared_ptr<HandshakeLimiter> limiter, std::string host)
      : limiter_(std::move(limiter)), host_(std::move(host)) {}
  HandshakeSlot(HandshakeSlot&& other) noexcept : limiter_(std::move(other.limiter_)), host_(std::move(other.host_)) {}
  HandshakeSlot& operator=(HandshakeSlot&& other) noexcept {
    if (this != &other) {
      end(false);
      limiter_ = std::move(other.limiter_);
      host_ = std::move(other.host_);
    }
    return *this;
  }
  ~HandshakeSlot() { end(false); }

  void completed() { end(true); }

 private:
  void end(bool completed) {
    if (limiter_) limiter_->finished(host_, completed);
    limiter_.reset();
  }
  std::shared_ptr<HandshakeLimiter> limiter_;
  std::string host_;
};

}  // namespace unima::tls
