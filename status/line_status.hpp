#pragma once
// An RS-485 line's row in the status document's "lines" (SPEC §18): what an operator asks
// of each port of the box — which role it plays, on which device and settings, whether it
// is open, the frames it sent and received, the bad ones, and what waits to go out. The
// slave service fills the slave line's row, the master service the master line's; /metrics
// labels each family by `line`. Pure.

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "status/statistic.hpp"

namespace unima::status {

/// What a line port counts on its wire.
struct LineCounters {
  std::uint64_t frames_sent = 0;
  std::uint64_t frames_received = 0;  // whole frames with a good CRC
  std::uint64_t errors = 0;           // frames with a bad CRC or length; a master's time-outs
};

struct LineStatus {
  std::string name;      // "rtu" for modbus.rtu
  std::string role;      // "slave", "master"
  std::string device;    // "/dev/ttyS1"
  std::string settings;  // "19200 8E1"
  bool open = false;
  LineCounters counters;
  std::uint64_t queue = 0;  // requests waiting for the line: a master's gateway requests, a slave's answers
};
void to_json(nlohmann::json& j, const LineStatus& s);
void from_json(const nlohmann::json& j, LineStatus& s);

const std::vector<Statistic<LineStatus>>& line_statistics();

}  // namespace unima::status
