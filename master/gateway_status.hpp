#pragma once
// The master's entries in the status document: each polled device's counts ("master") and
// the gateway's (SPEC §14, "gateway": its settings and each unit a client asked for), and
// their statistics.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "status/statistic.hpp"

namespace unima::master {

/// A foreign slave the master polls.
struct MasterDeviceStatus {
  std::uint64_t device = 0;  // its address
  std::uint64_t requests = 0;
  std::uint64_t answered = 0;
  std::uint64_t timeouts = 0;
  std::uint64_t exceptions = 0;
  std::uint64_t bad_frames = 0;
  std::uint64_t retries = 0;
};

/// How long forwarded requests waited for the line, in milliseconds.
struct WaitStatus {
  double last = 0;
  double mean = 0;
  double max = 0;
  std::uint64_t count = 0;
  double sum = 0;
};

/// A unit behind the gateway.
struct GatewayUnitStatus {
  std::uint64_t unit = 0;
  std::string state;                 // "answering", "not answering"
  std::optional<std::string> since;  // UTC, when it stopped answering
  std::uint64_t requests = 0;
  std::uint64_t answered = 0;
  std::uint64_t exceptions = 0;
  std::uint64_t timeouts = 0;
  std::uint64_t bad_frames = 0;
  std::uint64_t busy = 0;
  std::uint64_t cache_hits = 0;
  std::uint64_t queue_depth = 0;
  WaitStatus wait_ms;
};

struct GatewayStatus {
  std::string routes;  // "5-7, 9"
  std::vector<std::string> priority;
  std::int64_t wait_ms = 0;
  std::optional<std::int64_t> timeout_ms;  // none: each device's own
  std::int64_t cache_ms = 0;
  std::vector<GatewayUnitStatus> units;
};

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(MasterDeviceStatus, device, requests, answered, timeouts, exceptions,
                                                bad_frames, retries)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(WaitStatus, last, mean, max, count, sum)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(GatewayUnitStatus, unit, state, since, requests, answered, exceptions,
                                                timeouts, bad_frames, busy, cache_hits, queue_depth, wait_ms)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(GatewayStatus, routes, priority, wait_ms, timeout_ms, cache_ms, units)

const std::vector<status::Statistic<MasterDeviceStatus>>& master_device_statistics();
const std::vector<status::Statistic<GatewayUnitStatus>>& gateway_unit_statistics();

}  // namespace unima::master
