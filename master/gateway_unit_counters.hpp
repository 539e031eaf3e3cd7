#pragma once
// What the gateway has done for one unit id since a client first asked for it (SPEC §14,
// docs/gateway.md "Seen and counted"), for the status document and /metrics.

#include <cstdint>

#include "master/unit_answering.hpp"
#include "master/wait_time.hpp"

namespace unima::master {

struct GatewayUnitCounters {
  std::uint64_t requests = 0;    // sent on the line (never retried)
  std::uint64_t answered = 0;    // the slave's data
  std::uint64_t exceptions = 0;  // the slave's own exception answers
  std::uint64_t timeouts = 0;    // no answer: 0x0B
  std::uint64_t bad_frames = 0;  // bad CRC, too short, another address: 0x0B
  std::uint64_t busy = 0;        // not on the line within `wait`: 0x06
  std::uint64_t cache_hits = 0;  // answered from modbus.gateway.cache
  WaitTime wait;                 // from the request's arrival to the line
  UnitAnswering answering;
};

}  // namespace unima::master
