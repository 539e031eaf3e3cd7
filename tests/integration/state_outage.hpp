#pragma once
// A disk that refuses the state file's writes (issue 29, row 2), for the tests of every way
// a write comes in. Simulated without root: the daemon's file size limit is lowered below
// the state file's size (Daemon::limit_file_size), so its appends, and the rewrite that
// follows a failed one, fail with EFBIG as they would with ENOSPC.
//
// The set-up this needs: the daemon logs warnings only (its log is held to the limit too,
// and must stay below it to say why), the state file holds many values (every W and the
// outputs of 16 write blocks: larger than the log) and was compacted at the daemon's last
// start, so that no rewrite fits below its size as long as a refused value is as long as
// the one it replaces (fill() sets five-digit values).

#include <sys/resource.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/integration/bridge_fixture.hpp"

namespace unima::test::state_outage {

/// Config `blocks` lines: write blocks at 0x0200..0x020F for user outputs 1..16.
inline std::string write_blocks() {
  std::string blocks;
  for (int n = 1; n <= 16; ++n)
    blocks += "  - { type: write, register: " + std::to_string(0x0200 + n - 1) + ", output: " + std::to_string(n) + " }\n";
  return blocks;
}

/// Sets W+0..15 (from `w_base`) and the 16 outputs to 10000 + n over Modbus TCP; returns
/// the W values. The daemon must be restarted after it, so that the file is compacted.
inline std::vector<std::uint16_t> fill(std::uint16_t modbus_port, int w_base) {
  std::vector<std::uint16_t> values(16);
  for (std::uint16_t r = 0; r < 16; ++r) values[r] = static_cast<std::uint16_t>(10000 + r);
  ModbusClient client(modbus_port);
  EXPECT_TRUE(client.write_many(w_base, values));
  EXPECT_TRUE(client.write_many(0x0200, values));
  return values;
}

inline void refuse_writes(const Daemon& daemon, const std::filesystem::path& state_file) {
  daemon.limit_file_size(std::filesystem::file_size(state_file) - 1);
}

inline void take_writes(const Daemon& daemon) { daemon.limit_file_size(RLIM_INFINITY); }

}  // namespace unima::test::state_outage
