#pragma once
// Who has the master's line next when Modbus TCP clients reach the foreign slaves through
// the bridge (SPEC §14, docs/gateway.md): the decisions only, from time points the caller
// passes in — no clock, no I/O — so that every rule is unit-tested.
//
// - Requests of `priority` peers go first, before polls and other clients, oldest first.
// - Other clients are served in turn, one request per client per round, so that one
//   client sending without pause never starves another.
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
#include <optional>
#include <vector>

namespace unima::master {

class GatewayQueue {
 public:
  using Clock = std::chrono::steady_clock;
  using TimePoint = Clock::time_point;
  using Duration = Clock::duration;
  using Ticket = std::uint64_t;

  struct Request {
    Ticket ticket = 0;
    std::uint64_t client = 0;  // the connection: requests of one client are one turn
    bool priority = false;
    std::uint8_t unit = 0;
    TimePoint queued;
  };

  explicit GatewayQueue(Duration wait) : wait_(wait) {}

  /// A client's request joins the queue at `now`; its ticket names it from then on.
  Ticket push(std::uint64_t client, bool priority, std::uint8_t unit, TimePoint now);
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
  std::deque<Request> queue_;  // in the order they came
  Duration wait_;
  Ticket next_ticket_ = 1;
  std::optional<std::uint64_t> last_client_;  // the client served last in the round
  bool last_was_poll_ = true;
};

}  // namespace unima::master
