// A config from the command line through the one flow of configs from afar (SPEC §19,
// issue 40): `unima-bridge config apply|show|history|revert` against the real daemon —
// applied only once its probe passed and then kept across a restart; refused with the
// positions of its errors, a port it cannot bind, read_only on, or a change already under
// way; rolled back when its MQTT broker never accepts it (also after a kill -9 during the
// probe). The operator's file is never written.

#include <sys/stat.h>

#include <csignal>
#include <fstream>
#include <future>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/integration/bridge_fixture.hpp"
#include "tests/integration/cli_under_test.hpp"
#include "tests/integration/harness.hpp"

namespace unima::test {
namespace {

struct FileStamp {
  std::string bytes;
  timespec modified{};
};

FileStamp stamp_of(const std::filesystem::path& path) {
  struct stat st {};
  ::stat(path.c_str(), &st);
  return {read_file(path), st.st_mtim};
}

class RemoteConfigCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    config.modbus_port = free_port();
    config.feed_port = free_port();
    config.status_socket = (dir.path() / "control.sock").string();
    config.log_level = "info";
  }

  void start() {
    daemon = std::make_unique<Daemon>(dir, config.yaml());
    ASSERT_TRUE(wait_for_port(config.modbus_port)) << daemon->log();
    ASSERT_TRUE(eventually([&] { return std::filesystem::exists(config.status_socket); })) << daemon->log();
    operator_file = stamp_of(daemon->config_path());
  }

  // The operator's config with another Modbus TCP port: what a fleet would push.
  BridgeConfig moved_to(std::uint16_t port) const {
    auto next = config;
    next.modbus_port = port;
    return next;
  }

  CommandResult config_command(const std::string& words) const {
    return run(bridge_cli() + " config " + words + " --socket " + config.status_socket);
  }

  CommandResult apply(const std::string& yaml, const std::string& name = "sent.yaml") const {
    const auto file = dir.path() / name;
    std::ofstream(file) << yaml;
    return config_command("apply " + file.string() + " --timeout 60");
  }

  nlohmann::json status_json() const {
    return nlohmann::json::parse(run(bridge_cli() + " status --json --socket " + config.status_socket).output, nullptr, false);
  }

  bool serves_on(std::uint16_t port) const {
    ModbusClient client(port);
    return client.read_holding(0x0100, 1).has_value();
  }

  void expect_operator_file_untouched() const {
    const auto now = stamp_of(daemon->config_path());
    EXPECT_EQ(now.bytes, operator_file.bytes);
    EXPECT_EQ(now.modified.tv_sec, operator_file.modified.tv_sec);
    EXPECT_EQ(now.modified.tv_nsec, operator_file.modified.tv_nsec);
  }

  TempDir dir;
  BridgeConfig config;
  std::unique_ptr<Daemon> daemon;
  FileStamp operator_file;
};

TEST_F(RemoteConfigCliTest, AnAppliedConfigServesIsShownKeptAcrossARestartAndRevertedWithoutWritingTheOperatorFile) {
  start();
  const auto moved = free_port();
  const auto sent = moved_to(moved).yaml();
  const auto [code, output] = apply(sent);
  ASSERT_EQ(code, 0) << output << daemon->log();
  EXPECT_NE(output.find("applied"), std::string::npos) << output;
  EXPECT_TRUE(serves_on(moved));
  EXPECT_FALSE(serves_on(config.modbus_port));

  const auto status = status_json();
  ASSERT_TRUE(status.contains("config_in_force")) << status.dump();
  EXPECT_EQ(status["config_in_force"]["source"], "cli");
  EXPECT_EQ(status["config_in_force"]["number"], 1);
  EXPECT_EQ(status["config_in_force"]["last"]["result"], "applied");
  EXPECT_NE(run(bridge_cli() + " status --socket " + config.status_socket).output.find("remote config 1 from cli"),
            std::string::npos);
  EXPECT_TRUE(daemon->wait_for_log("remote config: cli by")) << daemon->log();

  const auto shown = config_command("show");
  EXPECT_EQ(shown.status, 0) << shown.output;
  EXPECT_NE(shown.output.find(sent), std::string::npos) << shown.output;
  const auto history = config_command("history");
  EXPECT_NE(history.output.find("in force"), std::string::npos) << history.output;
  expect_operator_file_untouched();

  // A restart with the operator's file unchanged: the config from afar stays in force.
  ASSERT_TRUE(daemon->terminate());
  daemon = std::make_unique<Daemon>(dir, config.yaml());
  ASSERT_TRUE(wait_for_port(moved)) << daemon->log();
  ASSERT_TRUE(eventually([&] { return std::filesystem::exists(config.status_socket); })) << daemon->log();
  EXPECT_EQ(status_json()["config_in_force"]["source"], "cli");

  const auto reverted = config_command("revert --timeout 60");
  ASSERT_EQ(reverted.status, 0) << reverted.output << daemon->log();
  EXPECT_TRUE(serves_on(config.modbus_port));
  EXPECT_EQ(status_json()["config_in_force"]["source"], "file");
}

TEST_F(RemoteConfigCliTest, AConfigWithErrorsIsRefusedWithTheirPositionsAndNothingChanges) {
  start();
  auto broken = moved_to(free_port());
  broken.extra += "no_such_section: 1\n";
  const auto yaml = broken.yaml();
  const auto line = std::count(yaml.begin(), yaml.begin() + static_cast<long>(yaml.find("no_such_section")), '\n') + 1;
  const auto [code, output] = apply(yaml, "broken.yaml");
  EXPECT_EQ(code, 1) << output;
  EXPECT_NE(output.find("refused"), std::string::npos) << output;
  EXPECT_NE(output.find((dir.path() / "broken.yaml").string() + ":" + std::to_string(line) + ":"), std::string::npos) << output;
  EXPECT_TRUE(serves_on(config.modbus_port));
  EXPECT_EQ(status_json()["config_in_force"]["source"], "file");
  EXPECT_EQ(status_json()["config_in_force"]["last"]["result"], "refused");
  EXPECT_NE(config_command("history").output.find("no config from afar"), std::string::npos);
}

TEST_F(RemoteConfigCliTest, AConfigWhosePortIsTakenIsRefusedAndTheRunningOneServesOn) {
  start();
  const auto taken = config.feed_port;  // the daemon's own feed listener holds it
  const auto [code, output] = apply(moved_to(taken).yaml());
  EXPECT_EQ(code, 1) << output;
  EXPECT_NE(output.find("refused: the config cannot be applied"), std::string::npos) << output;
  EXPECT_TRUE(serves_on(config.modbus_port));
}

TEST_F(RemoteConfigCliTest, WithReadOnlyOnNoConfigIsTaken) {
  config.tcp_extra = ", read_only: true";
  start();
  const auto [code, output] = apply(moved_to(free_port()).yaml());
  EXPECT_EQ(code, 1) << output;
  EXPECT_NE(output.find("read_only"), std::string::npos) << output;
  expect_operator_file_untouched();
}

// The broker the new config names never answers: after its probe the bridge goes back,
// and a second change sent meanwhile is told `busy`.
TEST_F(RemoteConfigCliTest, AConfigWhoseBrokerNeverAnswersIsRolledBackAndASecondChangeMeanwhileIsBusy) {
  start();
  auto unreachable = moved_to(free_port());
  unreachable.extra += "mqtt: { broker: mqtt://127.0.0.1:" + std::to_string(free_port()) + ", client_id: probe-test }\n"
                       "remote_config: { probe: 3s }\n";
  auto first = std::async(std::launch::async, [&] { return apply(unreachable.yaml(), "unreachable.yaml"); });
  ASSERT_TRUE(eventually([&] { return daemon->log().find("remote config: cli by") != std::string::npos; }));
  const auto second = apply(moved_to(free_port()).yaml(), "second.yaml");
  EXPECT_EQ(second.status, 1) << second.output;
  EXPECT_NE(second.output.find("busy"), std::string::npos) << second.output;
  const auto [code, output] = first.get();
  EXPECT_EQ(code, 1) << output;
  EXPECT_NE(output.find("rolled_back"), std::string::npos) << output;
  EXPECT_NE(output.find("MQTT broker"), std::string::npos) << output;
  EXPECT_TRUE(serves_on(config.modbus_port));
  EXPECT_EQ(status_json()["config_in_force"]["source"], "file");
}

// Killed while a change is probed: the change was never applied, so the restart runs the
// config before it.
TEST_F(RemoteConfigCliTest, AKillDuringTheProbeLeavesThePreviousConfigInForceAfterTheRestart) {
  start();
  const auto moved = free_port();
  auto unreachable = moved_to(moved);
  unreachable.extra += "mqtt: { broker: mqtt://127.0.0.1:" + std::to_string(free_port()) + ", client_id: probe-test }\n"
                       "remote_config: { probe: 30s }\n";
  auto first = std::async(std::launch::async, [&] { return apply(unreachable.yaml(), "unreachable.yaml"); });
  ASSERT_TRUE(wait_for_port(moved)) << daemon->log();
  daemon->signal(SIGKILL);
  EXPECT_NE(first.get().status, 0);
  daemon = std::make_unique<Daemon>(dir, config.yaml());
  ASSERT_TRUE(wait_for_port(config.modbus_port)) << daemon->log();
  ASSERT_TRUE(eventually([&] { return std::filesystem::exists(config.status_socket); })) << daemon->log();
  EXPECT_EQ(status_json()["config_in_force"]["source"], "file");
}

}  // namespace
}  // namespace unima::test
