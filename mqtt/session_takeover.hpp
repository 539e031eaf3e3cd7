#pragma once
// When a broker has given the bridge's session to another client with its id (SPEC §15):
// a broker lets one session have a client id, so two bridges with one id take it from each
// other, each reconnecting at once — a flap that floods the broker and the fleet's
// subscribers with `online`/`offline`. Once it is known, the bridge waits `retry_after`
// before it tries again, and the pair settles to a connection or two a minute each.
//
// How it is known:
// - MQTT 5: the broker says so, DISCONNECT with reason 0x8E "Session taken over".
// - MQTT 3.1.1 has no word for it: the broker just closes the connection. A connection
//   the broker closed (end of stream or a reset, not a keep-alive or another error)
//   within `short_session` of its CONNACK is a sign; the second such connection in a row,
//   and every one after it until a connection lasts longer or ends otherwise, is taken
//   for a takeover. One alone is not: a broker restarting or an ACL reload closes a young
//   connection too, and the normal back-off handles those. `short_session` is longer than
//   `retry_after`, so that a bridge whose session another takes after its 30 s wait is
//   held back as well and the pair does not flap in turns.
// Pure: the times are passed in.

#include <chrono>
#include <optional>
#include <utility>

namespace unima::mqtt {

/// How a connection that had been made ended.
enum class ConnectionEnd {
  taken_over,        // MQTT 5 DISCONNECT 0x8E
  closed_by_broker,  // the stream ended or was reset by the other side
  failed,            // anything else: keep-alive, an error of ours, the network
};

class SessionTakeover {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr std::chrono::seconds short_session{60};
  static constexpr std::chrono::seconds retry_after{30};

  /// A CONNACK that accepted the connection.
  void connected(Clock::time_point at) { connected_at_ = at; }
  /// The connection made last ended: whether its session was taken over.
  bool ended(ConnectionEnd end, Clock::time_point at);

 private:
  std::optional<Clock::time_point> connected_at_;
  int short_closes_in_a_row_ = 0;
};

static_assert(SessionTakeover::retry_after < SessionTakeover::short_session, "or a pair sharing an id flaps in turns");

}  // namespace unima::mqtt
