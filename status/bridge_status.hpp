#pragma once
// The bridge's own part of the status document — not an object of its own but the
// document's top-level keys (pid, config, uptime_s, rss_bytes, mode, the addresses, the
// Error LED, online_bits), written by app/bridge before each service adds its part — and
// its statistics.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "status/statistic.hpp"

namespace unima::status {

struct BridgeStatus {
  std::int64_t pid = 0;
  std::string config;                      // the config file it runs
  std::int64_t uptime_s = 0;               // since the daemon started
  std::optional<std::uint64_t> rss_bytes;  // resident memory; none where the kernel does not say (left out)
  std::string mode;                        // "slave" or "master"
  std::uint64_t modbus_address = 0;
  std::uint64_t unimabus_address = 0;
  bool error = false;  // the Modbus error bit (C+0x13 bit 15, the front panel's Error LED)
  std::uint64_t online_bits = 0;  // C+0x13
};
/// `j` becomes an object of these keys only: the services add theirs after.
void to_json(nlohmann::json& j, const BridgeStatus& s);
/// Read from the whole document; the services' keys are theirs.
void from_json(const nlohmann::json& j, BridgeStatus& s);

const std::vector<Statistic<BridgeStatus>>& bridge_statistics();

}  // namespace unima::status
