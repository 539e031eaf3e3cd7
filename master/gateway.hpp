#pragma once
// The gateway's decisions (SPEC §14, docs/gateway.md), in one place and without I/O: a
// client's request for a foreign slave arrives, waits for the line, goes on it and ends
// with an answer, and this says at each step what happens — from the cache or the queue,
// whose turn, which time-out, what the client is answered, what each unit's outcome
// counts as, when the cache is emptied, and the gateway's own exception answers:
// 0x06 (not on the line within `wait`), 0x0B (no good answer). 0x0A, a unit the gateway
// does not route, is modbus::route's.
//
// io/master/master_port moves the bytes: it calls these with the time points it reads
// and the frames the link returns, and sends what they say.

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <vector>

#include "master/gateway_cache.hpp"
#include "master/gateway_queue.hpp"
#include "master/gateway_unit_counters.hpp"
#include "master/master_codec.hpp"
#include "modbus/protocol.hpp"

namespace unima::master {

/// The gateway's own exception answer to a request of `function`: function | 0x80, `code`.
Bytes gateway_exception(std::uint8_t function, modbus::ExceptionCode code);

class Gateway {
 public:
  using Clock = std::chrono::steady_clock;
  using TimePoint = Clock::time_point;
  using Ticket = GatewayQueue::Ticket;

  struct Settings {
    Clock::duration wait{};                         // modbus.gateway.wait
    std::optional<std::chrono::milliseconds> timeout;  // modbus.gateway.timeout
    Clock::duration cache{};                        // modbus.gateway.cache; zero: no cache
  };

  explicit Gateway(Settings settings);

  /// A client's request arrives at `now`: either answered from the cache (the answer PDU,
  /// counted as a cache hit), or queued for the line under the returned ticket, or
  /// neither when its host has too many waiting (GatewayQueue; counted busy, answered 0x06).
  struct Arrival {
    std::optional<Bytes> cached;
    std::optional<Ticket> ticket;
  };
  Arrival arrive(const GatewayQueue::Asker& asker, std::uint8_t unit, std::span<const std::uint8_t> pdu, TimePoint now);

  /// The queued request that has the line next, when the line is free; nullopt when none
  /// waits or a due poll (`poll_due`) has its turn (GatewayQueue).
  std::optional<GatewayQueue::Request> next(bool poll_due) const { return queue_.next(poll_due); }
  /// `next` takes the line at `now` with `pdu`: counted, its wait measured; a write empties
  /// its unit's cache again (a read answered while it waited saw the slave before it).
  void began(const GatewayQueue::Request& next, std::span<const std::uint8_t> pdu, TimePoint now);
  /// How long to wait for `unit`'s answer: modbus.gateway.timeout; else the polled
  /// device's own response time-out (`device_timeout`, when the master polls it); else 1 s.
  std::chrono::milliseconds timeout(std::optional<Clock::duration> device_timeout) const;

  /// What a forwarded transaction ended with: the answer for the client, the monitor's
  /// state, whether it lights the Error LED, and whether the unit stopped or started
  /// answering with it (for the log).
  struct Outcome {
    Bytes answer;
    MasterResponse result;
    UnitAnswering::Transition transition = UnitAnswering::Transition::none;
  };
  /// The request `pdu` for `unit`, sent at `sent`, got `frame` back (empty: no answer) by
  /// `now`: the slave's own answer (data or its exception) when it answers this request
  /// (master::check_forwarded_rtu_answer), kept by the cache when it is data and the line's
  /// transaction before it did not time out (a late answer may have been on the line);
  /// else 0x0B, never kept.
  Outcome finished(std::uint8_t unit, std::span<const std::uint8_t> pdu, std::span<const std::uint8_t> frame,
                   TimePoint now, std::chrono::system_clock::time_point sent);

  /// The requests that have waited `wait` by `now` without the line, removed and counted
  /// busy; each is answered 0x06.
  std::vector<GatewayQueue::Request> expire(TimePoint now);
  std::optional<TimePoint> next_expiry() const { return queue_.next_expiry(); }
  /// A client's connection closed: its queued requests leave the queue (their tickets).
  std::vector<Ticket> client_gone(std::uint64_t client);

  /// The master's own poll took the line: the next forwarded request goes before the next poll.
  void poll_began() { queue_.poll_began(); }
  /// The master's own poll ended; `timed_out` when it got no answer.
  void poll_ended(bool timed_out) { after_timeout_ = timed_out; }
  /// The master's own send writes to `unit`: the slave changes as with a client's write.
  void device_written(std::uint8_t unit);

  std::size_t waiting() const { return queue_.size(); }
  std::size_t queue_depth(std::uint8_t unit) const { return queue_.waiting_for(unit); }
  /// Each unit id a client has asked for since the gateway started.
  const std::map<std::uint8_t, GatewayUnitCounters>& units() const { return units_; }

 private:
  Settings settings_;
  GatewayQueue queue_;
  std::optional<GatewayCache> cache_;
  std::map<std::uint8_t, GatewayUnitCounters> units_;
  bool after_timeout_ = false;  // the line's last transaction got no answer
};

}  // namespace unima::master
