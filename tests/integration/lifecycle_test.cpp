// The daemon's life: SIGTERM, SIGHUP reload (good and bad configs), bad start-up configs,
// and `unima-bridge check`.

#include <signal.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>

#include "tests/integration/bridge_fixture.hpp"

namespace unima::test {
namespace {

class Lifecycle : public BridgeTest {};

// The line number of a line appended to `yaml`.

TEST_F(Lifecycle, StopsWithinASecondOfSigterm) {
  start();
  ModbusClient client(config.modbus_port);  // a connected client does not hold it up
  ASSERT_TRUE(client.read_input(0x0011, 1));
  auto feed = feed_client();
  const auto took = daemon->terminate();
  ASSERT_TRUE(took) << "still running 5 s after SIGTERM";
  EXPECT_LT(took->count(), 1000);
  EXPECT_EQ(daemon->exit_code(), 0);
}

TEST_F(Lifecycle, ReloadAppliesANewConfigAndKeepsConnectionsAndValues) {
  start();
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.write(0x0100, 42));
  auto feed = feed_client();
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":0,"values":[80]})", 0x0011, 80);

  config.banks = "{ D1: 0x0011, W: 0x0200 }";
  daemon->rewrite_config(config.yaml());
  daemon->signal(SIGHUP);
  ASSERT_TRUE(daemon->wait_for_log("reloaded")) << daemon->log();
  EXPECT_EQ(client.read_input(0x0200, 1), std::vector<std::uint16_t>{42});  // same connection, W moved
  EXPECT_FALSE(client.read_input(0x0100, 1));
  EXPECT_EQ(client.read_input(0x0011, 1), std::vector<std::uint16_t>{80});  // D1 kept its value
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":0,"values":[81]})", 0x0011, 81);  // feed kept
}

TEST_F(Lifecycle, ABadReloadIsLoggedAndTheOldConfigKeepsServing) {
  start();
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.write(0x0100, 7));
  const auto good = config.yaml();
  daemon->rewrite_config(good + "modbus_typo: 1\n");
  daemon->signal(SIGHUP);
  ASSERT_TRUE(daemon->wait_for_log("reload failed, the running config stays")) << daemon->log();
  EXPECT_NE(daemon->log().find("bridge.yaml:" + next_line(good) + ":1: unknown key 'modbus_typo'"), std::string::npos)
      << daemon->log();
  EXPECT_EQ(client.read_input(0x0100, 1), std::vector<std::uint16_t>{7});
  ModbusClient fresh(config.modbus_port);
  EXPECT_EQ(fresh.read_input(0x0100, 1), std::vector<std::uint16_t>{7});
  EXPECT_TRUE(daemon->running());
}

TEST_F(Lifecycle, AReloadToATakenPortKeepsTheOldPort) {
  start();
  const auto blocker_port = config.feed_port;  // taken by the daemon's own feed listener
  auto moved = config;
  moved.modbus_port = blocker_port;
  daemon->rewrite_config(moved.yaml());
  daemon->signal(SIGHUP);
  ASSERT_TRUE(daemon->wait_for_log("reload failed")) << daemon->log();
  ModbusClient client(config.modbus_port);
  EXPECT_TRUE(client.read_input(0x0011, 1));
}

// The log level is staged with the rest of the config: a reload the bridge refuses (its
// port is taken) leaves the running level, so the next SIGHUP's info line is still logged.
TEST_F(Lifecycle, ARefusedReloadKeepsTheRunningLogLevel) {
  start();
  auto quiet = config;
  quiet.modbus_port = config.feed_port;  // taken by the daemon's own feed listener
  quiet.log_level = "error";
  daemon->rewrite_config(quiet.yaml());
  daemon->signal(SIGHUP);
  ASSERT_TRUE(eventually([&] { return daemon->log_count("reload failed") == 1; })) << daemon->log();
  daemon->signal(SIGHUP);
  ASSERT_TRUE(eventually([&] { return daemon->log_count("reload failed") == 2; })) << daemon->log();
  EXPECT_EQ(daemon->log_count("SIGHUP: reloading"), 2) << daemon->log();
}

TEST_F(Lifecycle, ABadConfigAtStartUpExitsNonZeroNamingThePosition) {
  const auto good = config.yaml();
  daemon = std::make_unique<Daemon>(dir, good + "banks2: {}\n");
  ASSERT_TRUE(eventually([&] { return !daemon->running(); }));
  EXPECT_EQ(daemon->exit_code(), 1);
  EXPECT_NE(daemon->log().find("bridge.yaml:" + next_line(good) + ":1: unknown key 'banks2'"), std::string::npos)
      << daemon->log();
}

// `unima-bridge SUB --help` answers as `man` would be asked: its usage line, exit 0 (it
// said "unknown argument" for check and map, printed every table for tables).
TEST(CheckCommand, EverySubcommandAnswersHelpWithItsUsage) {
  for (const std::string sub : {"check", "map", "tables", "profiles", "status", "monitor"}) {
    const auto r = run(std::string(UNIMA_BRIDGE_CLI) + " " + sub + " --help 2>&1");
    EXPECT_EQ(r.status, 0) << sub << ": " << r.output;
    EXPECT_TRUE(r.output.starts_with("usage: unima-bridge " + sub)) << sub << ": " << r.output.substr(0, 200);
  }
}

TEST(CheckCommand, AcceptsTheDemoConfig) {
  const auto r = run(std::string(UNIMA_BRIDGE_CLI) + " check --config " UNIMA_SOURCE_DIR "/config/examples/demo.yaml");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("0x1100..0x113F  bank D1"), std::string::npos) << r.output;
}

TEST(CheckCommand, RejectsOverlapsNamingBothBanks) {
  TempDir dir;
  const auto path = dir.path() / "overlap.yaml";
  std::FILE* f = std::fopen(path.c_str(), "w");
  std::fputs("devices:\n  D1: { type: unigen-chp, address: 5 }\nbanks: { D1: 0x0011, W: 0x0040 }\n", f);
  std::fclose(f);
  const auto r = run(std::string(UNIMA_BRIDGE_CLI) + " check --config " + path.string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.output.find("overlap.yaml:3:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("bank D1 (0x0011..0x0050) overlaps bank W (0x0040..0x004F)"), std::string::npos) << r.output;
}

// A D_N is 64 registers whatever its type (seed §6.1): a bank placed right after a USC's
// table of 40 now overlaps the USC's window, and `check` names both.
TEST(CheckCommand, ADeviceBankIsTheSeedsWindowOf64Registers) {
  TempDir dir;
  const auto write = [&](const std::string& name, const std::string& text) {
    const auto path = dir.path() / name;
    std::FILE* f = std::fopen(path.c_str(), "w");
    std::fputs(text.c_str(), f);
    std::fclose(f);
    return path.string();
  };
  const auto alone = run(std::string(UNIMA_BRIDGE_CLI) + " check --config " +
                         write("usc.yaml", "devices:\n  D2: { type: usc, address: 5 }\n"));
  EXPECT_EQ(alone.status, 0) << alone.output;
  EXPECT_NE(alone.output.find("0x1200..0x123F  bank D2"), std::string::npos) << alone.output;
  const auto crowded = run(std::string(UNIMA_BRIDGE_CLI) + " check --config " +
                           write("crowded.yaml", "devices:\n  D2: { type: usc, address: 5 }\nbanks: { D2: 0x1200, S1: 0x1230 }\n"));
  EXPECT_EQ(crowded.status, 1) << crowded.output;
  EXPECT_NE(crowded.output.find("bank D2 (0x1200..0x123F) overlaps bank S1 (0x1230..0x1243)"), std::string::npos)
      << crowded.output;
}

TEST(CheckCommand, UsageErrorsExitTwo) {
  EXPECT_EQ(run(std::string(UNIMA_BRIDGE_CLI)).status, 2);
  EXPECT_EQ(run(std::string(UNIMA_BRIDGE_CLI) + " frobnicate").status, 2);
  EXPECT_EQ(run(std::string(UNIMA_BRIDGE_CLI) + " check").status, 2);
}

}  // namespace
}  // namespace unima::test
