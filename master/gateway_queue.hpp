#pragma once
// Who has the master's line next when Modbus TCP clients reach the foreign slaves through
// the bridge (SPEC §14, docs/gateway.md): the decisions only, from time points the caller
// passes in — no clock, no I/O — so that every rule is unit-tested.
//
// - Requests of `priority` peers go first, before polls and other clients, oldest first.
// - Other clients are served in turn by host, then by connection: one request per host per
//   round, and within a host's turns one per connection, so that neither one client
//   sending without pause nor one host opening many connections starves another.
// - A host has at most `most_waiting_per_host` requests waiting: one more is refused at
//   once (the caller answers it "slave device busy", 0x06, as it would after `wait`).
// - Polls and forwarded requests take turns: when a poll is due and the line's last
//   transaction was a forwarded one, the poll goes first, so polls keep their period
//   while clients use at most about half of the line.
// - A request that has waited `wait` without getting the line leaves the queue: it is
//   answered "slave device busy" (0x06) by the caller.
//
// The line itself (one transaction at a time, t3.5 between frames, a device's min_gap) is
// MasterScheduler's: it says when the line is free, this says for whom.

#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace unima::master {

class GatewayQueue {
 public:
  using Clock = std::chrono::steady_clock;
  using TimePoint = Clock::time_point;
  using Duration = Clock::duration;
  using Ticket = std::uint64_t;

  /// Who asks: a connection, the host it comes from, whether the host is a priority peer.
  struct Asker {
    std::uint64_t client = 0;
    std::string host;
    bool priority = false;
  };

  struct Request {
    Ticket ticket = 0;
    std::uint64_t client = 0;  // the connection: requests of one client are one turn
    std::string host;          // its peer's address: hosts take turns before connections do
    bool priority = false;
    std::uint8_t unit = 0;
    TimePoint queued;
  };

  /// Enough for a SCADA's or an OPC server's handful of connections, each with one request
  /// waiting (a connection waits for its answer before its next request goes on).
  static constexpr std::size_t most_waiting_per_host = 16;

  explicit GatewayQueue(Duration wait) : wait_(wait) {}

  /// A client's request joins the queue at `now`; its ticket names it from then on.
  /// nullopt: its host (not a priority peer) already has most_waiting_per_host waiting.
  std::optional<Ticket> push(const Asker& asker, std::uint8_t unit, TimePoint now);
  /// The request that has the line next, when the line is free; nullopt when none waits
  /// or a due poll (`poll_due`) has its turn.
  std::optional<Request> next(bool poll_due) const;
  /// `ticket` (from next()) took the line: it leaves the queue, and its client had its turn.
  void began(Ticket ticket);
  /// A poll took the line: the next forwarded request goes before the next poll.
  void poll_began() { last_was_poll_ = true; }
  /// The requests that waited `wait` by `now` without the line, removed, oldest first.
  std::vector<Request> expire(TimePoint now);
  /// When the oldest request will have waited `wait`; nullopt when none waits.
  std::optional<TimePoint> next_expiry() const;
  /// The requests of a client that has gone, removed.
  std::vector<Request> drop_client(std::uint64_t client);

  std::size_t size() const { return queue_.size(); }
  /// The requests for `unit` waiting now (the gateway's queue depth of a unit).
  std::size_t waiting_for(std::uint8_t unit) const;
  bool empty() const { return queue_.empty(); }

 private:
  struct Host {
    std::size_t waiting = 0;                    // its requests in the queue, priority ones aside
    std::optional<std::uint64_t> last_client;  // its connection served last in its turns
  };
  void left(const Request& request);
  void forget_if_idle(const std::string& host);

  std::deque<Request> queue_;  // in the order they came
  Duration wait_;
  Ticket next_ticket_ = 1;
  std::map<std::string, Host, std::less<>> hosts_;  // see forget_if_idle
  std::optional<std::string> last_host_;           // the host served last in the round
  bool last_was_poll_ = true;
};

}  // namespace unima::master
