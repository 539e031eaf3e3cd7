// Which config runs at start and on SIGHUP (app/config_in_force, SPEC §19): the remote
// config in force while the operator's file is byte for byte the one it replaced, else the
// file — told to the store and said in the log; a kept text that no longer loads gives way
// to the file; a kept text means what it would in the operator's file's place.

#include <gtest/gtest.h>

#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>

#include "app/config_in_force.hpp"
#include "tests/support/error_message.hpp"
#include "tests/support/temp_files.hpp"

namespace unima::app {
namespace {

using test_support::TempDir;
namespace fs = std::filesystem;

class ConfigInForceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    previous_logger_ = spdlog::default_logger();
    auto logger = std::make_shared<spdlog::logger>("test", std::make_shared<spdlog::sinks::ostream_sink_st>(log_));
    logger->set_pattern("%l %v");
    spdlog::set_default_logger(logger);
    operator_path = (dir.path() / "bridge.yaml").string();
    write_operator_file(operator_text);
  }
  void TearDown() override { spdlog::set_default_logger(previous_logger_); }

  void write_operator_file(const std::string& text) const { test_support::write_file(operator_path, text); }
  /// The store the operator's file's default state file (dir/bridge.state) leads to.
  io::RemoteConfigStore store() const { return io::RemoteConfigStore(dir.path() / "remote-config", 10); }
  /// `text` kept in force, as having replaced the operator's file as it is now.
  io::StoredConfig keep_in_force(const std::string& text) const {
    auto kept = store();
    return kept.keep(text, remote::Source::mqtt, "bridge-fleet-1", operator_path,
                     remote::change_id(test_support::read_file(operator_path)), std::nullopt,
                     std::chrono::system_clock::time_point(std::chrono::seconds(1'795'991'405)));
  }
  std::string log() const { return log_.str(); }

  TempDir dir;
  std::string operator_path;
  // The host's environment is empty: the state file goes beside the config, in `dir`.
  config::Host host;
  std::string socket_line() const { return "status: { socket: " + (dir.path() / "control.sock").string() + " }\n"; }
  const std::string operator_text = "modbus: { address: 3 }\n";

 private:
  std::ostringstream log_;
  std::shared_ptr<spdlog::logger> previous_logger_;
};

TEST_F(ConfigInForceTest, WithNothingKeptTheFileRunsAndNothingIsMade) {
  const auto chosen = load_config_in_force(operator_path, host);
  EXPECT_FALSE(chosen.remote);
  EXPECT_EQ(chosen.config.modbus.address, 3);
  EXPECT_EQ(chosen.config.file, operator_path);
  EXPECT_EQ(chosen.operator_file, operator_path);
  EXPECT_EQ(chosen.operator_sha256, remote::change_id(operator_text));
  EXPECT_EQ(chosen.store_directory, dir.path() / "remote-config");
  EXPECT_FALSE(fs::exists(dir.path() / "remote-config"));
}

TEST_F(ConfigInForceTest, TheRemoteConfigRunsWhileTheFileIsUnchanged) {
  const auto kept = keep_in_force("modbus: { address: 9 }\n");
  const auto chosen = load_config_in_force(operator_path, host);
  ASSERT_TRUE(chosen.remote);
  EXPECT_EQ(*chosen.remote, kept);
  EXPECT_EQ(chosen.config.modbus.address, 9);
  EXPECT_EQ(chosen.config.file, kept.text_path.string());  // its errors and status name where it is kept
  EXPECT_EQ(chosen.config.file_sha256, kept.id);
  EXPECT_EQ(chosen.operator_sha256, remote::change_id(operator_text));
  EXPECT_NE(log().find("remote config 1 (mqtt, by bridge-fleet-1, at 2026-11-29T22:30:05.000000Z) is in force in place of " +
                       operator_path),
            std::string::npos)
      << log();
  EXPECT_EQ(test_support::read_file(operator_path), operator_text);
}

TEST_F(ConfigInForceTest, AChangedFileWinsTheStoreIsToldAndTheLogSaysSo) {
  keep_in_force("modbus: { address: 9 }\n");
  write_operator_file("modbus: { address: 4 }\n");
  const auto chosen = load_config_in_force(operator_path, host);
  EXPECT_FALSE(chosen.remote);
  EXPECT_EQ(chosen.config.modbus.address, 4);
  EXPECT_FALSE(store().in_force());
  EXPECT_EQ(store().history().size(), 1u);  // the history stays
  EXPECT_NE(log().find("warning remote config: " + operator_path +
                       " changed since remote config 1 was applied (by bridge-fleet-1, at 2026-11-29T22:30:05.000000Z); "
                       "the file is in force"),
            std::string::npos)
      << log();
  // Changed back, the file stays in force: the store was told.
  write_operator_file(operator_text);
  EXPECT_FALSE(load_config_in_force(operator_path, host).remote);
}

TEST_F(ConfigInForceTest, AKeptTextThatNoLongerLoadsGivesWayToTheFile) {
  const auto kept = keep_in_force("modbus:\n  address: 900\n");
  const auto chosen = load_config_in_force(operator_path, host);
  EXPECT_FALSE(chosen.remote);
  EXPECT_EQ(chosen.config.modbus.address, 3);
  EXPECT_NE(log().find("error remote config: remote config 1 no longer loads; the file " + operator_path +
                       " is in force: " + kept.text_path.string() + ":2:12: "),
            std::string::npos)
      << log();
  EXPECT_TRUE(store().in_force());  // not told: the next start or SIGHUP tries it again
}

TEST_F(ConfigInForceTest, AKeptTextMeansWhatItWouldInTheOperatorsFile) {
  keep_in_force("modbus: { address: 9 }\nmqtt: { broker: mqtt://127.0.0.1:1883 }\nmonitor: { file: monitor.log }\n" +
                socket_line());
  const auto chosen = load_config_in_force(operator_path, host);
  ASSERT_TRUE(chosen.remote);
  // What goes beside the config goes beside the operator's file, not beside the kept text.
  EXPECT_EQ(chosen.config.state.file, (dir.path() / "bridge.state").string());
  EXPECT_EQ(chosen.config.mqtt->buffer.file, (dir.path() / "bridge.mqtt-buffer").string());
  // A relative path is from the daemon's working directory, as in the operator's file.
  EXPECT_EQ(chosen.config.monitor.file, "monitor.log");
}

TEST_F(ConfigInForceTest, TheOperatorsFileOwnErrorsThrowAsLoadFileDoes) {
  keep_in_force("modbus: { address: 9 }\n");
  write_operator_file("modbus: { address: 3 }\nmodbus_typo: 1\n");
  const auto message = test_support::error_message<config::ConfigError>([&] { load_config_in_force(operator_path, host); });
  EXPECT_TRUE(message.starts_with(operator_path + ":2:1: unknown key 'modbus_typo'")) << message;
  const auto missing = (dir.path() / "missing.yaml").string();
  EXPECT_TRUE(test_support::error_message<config::ConfigError>([&] { load_config_in_force(missing, host); })
                  .starts_with(missing + ": cannot open the config file: "));
}

TEST_F(ConfigInForceTest, TheStoreOfTheStartStaysWhenTheFileNamesAnotherStateFile) {
  keep_in_force("modbus: { address: 9 }\n");
  const auto at_start = load_config_in_force(operator_path, host);
  ASSERT_TRUE(at_start.remote);
  // The operator moves the state file: a change of the file, which wins, told to the store
  // the daemon runs with.
  write_operator_file(operator_text + "state: { file: " + (dir.path() / "elsewhere" / "state").string() + " }\n");
  const auto reloaded = load_config_in_force(operator_path, at_start.store_directory, host);
  EXPECT_FALSE(reloaded.remote);
  EXPECT_EQ(reloaded.store_directory, dir.path() / "remote-config");
  EXPECT_FALSE(store().in_force());
}

TEST_F(ConfigInForceTest, WithoutAStateFileNothingIsKeptAndTheFileRuns) {
  write_operator_file(operator_text + "state: { file: none }\n");
  const auto chosen = load_config_in_force(operator_path, host);
  EXPECT_FALSE(chosen.remote);
  EXPECT_TRUE(chosen.store_directory.empty());
}

}  // namespace
}  // namespace unima::app
