#pragma once
// On a shared RTU line the bridge hears a foreign master talk to other slaves (Not4Me,
// seed 004 §8). This pairs each such query with the response that follows it, so that
// the monitor logs the exchange as one transaction and capture blocks see the answer; a
// query is given up unanswered when anything else comes first (a query, a bad frame) or
// after `give_up_after`. Pure: the port feeds it frames and times and arms one timer at
// deadline().

#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "modbus/rtu/rtu_framer.hpp"

namespace unima::modbus {

class BusListener {
 public:
  struct Exchange {
    std::vector<std::uint8_t> query;
    std::vector<std::uint8_t> response;  // empty: none was heard
  };

  explicit BusListener(RtuClock::duration give_up_after) : give_up_after_(give_up_after) {}

  /// Another slave's query heard at `now`; it now waits for its response.
  void heard_query(std::span<const std::uint8_t> query, RtuClock::time_point now);
  /// A response heard: the exchange it completes, or nullopt when no query waited (its
  /// query was given up).
  std::optional<Exchange> heard_response(std::span<const std::uint8_t> response);
  /// Anything else on the line, or the line lost: the waiting query, unanswered.
  std::optional<Exchange> interrupted();
  /// When the waiting query is given up; nullopt when none waits.
  std::optional<RtuClock::time_point> deadline() const;
  /// The waiting query, unanswered, once `now` is past deadline().
  std::optional<Exchange> expire(RtuClock::time_point now);

 private:
  RtuClock::duration give_up_after_;
  std::optional<std::vector<std::uint8_t>> waiting_;
  RtuClock::time_point heard_at_;
};

}  // namespace unima::modbus
