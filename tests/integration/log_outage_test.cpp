// The monitor log on a failing disk (issue 17 item 4, SPEC §10): the journal says so once
// and says once that it works again — not hundreds of lines a second.
//
// A full disk is simulated without root: the daemon's file size limit (RLIMIT_FSIZE, set
// from here with prlimit(2)) is lowered to the log's size and raised again, over and over.
// Writes past the limit fail with EFBIG, as they fail with ENOSPC on a full disk whose
// failed writes are cut back and free a little room: failing and succeeding in turn.

#include <sys/resource.h>

#include <filesystem>
#include <thread>

#include "tests/integration/bridge_fixture.hpp"

namespace unima::test {
namespace {

class LogOutage : public BridgeTest {
 protected:
  void limit_file_size(rlim_t bytes) const { daemon->limit_file_size(bytes); }
  /// Reads for `how_long`, each a line in the monitor log.
  void poll(ModbusClient& client, std::chrono::milliseconds how_long) const {
    const auto until = std::chrono::steady_clock::now() + how_long;
    while (std::chrono::steady_clock::now() < until) {
      ASSERT_TRUE(client.read_input(0x0011, 1)) << daemon->log();
      std::this_thread::sleep_for(5ms);  // a SCADA's pace: reads spread over `how_long`, not a flood
    }
  }
};

TEST_F(LogOutage, AFlappingFullDiskIsLoggedOnceAndItsRecoveryOnce) {
  const auto log = dir.path() / "monitor.log";
  config.monitor_section = "monitor:\n  file: " + log.string() + "\n";
  start();
  ModbusClient client(config.modbus_port);
  // A log larger than the daemon's own, which the limit must spare: reads until it is (a
  // loaded machine answers fewer of them in a given time), at most 10 s of them.
  for (int i = 0; i < 200 && std::filesystem::file_size(log) <= 8192; ++i) poll(client, 50ms);
  ASSERT_GT(std::filesystem::file_size(log), 8192u) << daemon->log();

  for (int i = 0; i < 12; ++i) {  // full for 120 ms, then room for 120 ms
    limit_file_size(std::filesystem::file_size(log));
    poll(client, 120ms);
    limit_file_size(RLIM_INFINITY);
    poll(client, 120ms);
  }
  ASSERT_TRUE(daemon->running()) << daemon->log();
  EXPECT_EQ(daemon->log_count("monitor: cannot write " + log.string()), 1u) << daemon->log();
  EXPECT_EQ(daemon->log_count("monitor: writing " + log.string() + " again"), 0u) << daemon->log();

  // Writing has worked for a while: its end is logged, once.
  poll(client, 6s);
  EXPECT_TRUE(daemon->wait_for_log("monitor: writing " + log.string() + " again")) << daemon->log();
  poll(client, 500ms);
  EXPECT_EQ(daemon->log_count("monitor: cannot write"), 1u) << daemon->log();
  EXPECT_EQ(daemon->log_count("monitor: writing " + log.string() + " again"), 1u) << daemon->log();
  EXPECT_NE(daemon->log().find("writes failed over"), std::string::npos) << daemon->log();
  EXPECT_EQ(read_file(log).back(), '\n');  // whole lines only, lost ones cut back
}

}  // namespace
}  // namespace unima::test
