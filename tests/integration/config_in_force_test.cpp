// The real daemon on a remote config kept in its state directory (SPEC §19, "Where it
// lives"): the remote config serves from the start and through SIGHUP and restarts while the
// operator's file is unchanged; once the file changed, the file wins and the log says so.
// The operator's file is never written by the daemon: its bytes and mtime are compared.

#include <signal.h>
#include <sys/stat.h>

#include <chrono>
#include <string>

#include "io/remote_config_store.hpp"
#include "tests/integration/bridge_fixture.hpp"

namespace unima::test {
namespace {

struct FileSeen {
  std::string bytes;
  timespec mtime{};
  bool operator==(const FileSeen& other) const {
    return bytes == other.bytes && mtime.tv_sec == other.mtime.tv_sec && mtime.tv_nsec == other.mtime.tv_nsec;
  }
};

FileSeen file_seen(const std::filesystem::path& path) {
  struct stat st{};
  if (::stat(path.c_str(), &st) != 0) return {};
  return {read_file(path), st.st_mtim};
}

class ConfigInForce : public BridgeTest {
 protected:
  void SetUp() override {
    BridgeTest::SetUp();
    // The remote config: another TCP port, and W moved from 0x0100 to 0x0200.
    remote = config;
    remote.modbus_port = free_port();
    remote.banks = "{ D1: 0x0011, W: 0x0200 }";
  }
  /// `remote` kept in force in the store of the operator's file DIR/bridge.yaml (its default
  /// state file is DIR/bridge.state), as having replaced `operator_yaml`.
  io::StoredConfig keep_remote(const std::string& operator_yaml) const {
    io::RemoteConfigStore store(dir.path() / "remote-config", io::RemoteConfigStore::default_keep);
    return store.keep(remote.yaml(), remote::Source::cli, "integrator", (dir.path() / "bridge.yaml").string(),
                      remote::change_id(operator_yaml), std::nullopt, std::chrono::system_clock::now());
  }
  /// The remote config serves: its port, its layout; the operator's port does not.
  void expect_remote_serves() const {
    ASSERT_TRUE(wait_for_port(remote.modbus_port)) << daemon->log();
    ModbusClient client(remote.modbus_port);
    EXPECT_TRUE(client.write(0x0200, 42)) << daemon->log();
    EXPECT_FALSE(client.read_input(0x0100, 1));
    EXPECT_FALSE(Socket::tcp(config.modbus_port).valid());
  }
  void expect_file_serves() const {
    ASSERT_TRUE(wait_for_port(config.modbus_port)) << daemon->log();
    ModbusClient client(config.modbus_port);
    EXPECT_TRUE(client.write(0x0100, 43)) << daemon->log();
    EXPECT_FALSE(client.read_input(0x0200, 1));
    EXPECT_TRUE(eventually([&] { return !Socket::tcp(remote.modbus_port).valid(); })) << daemon->log();
  }

  BridgeConfig remote;
};

TEST_F(ConfigInForce, TheRemoteConfigServesThroughSighupUntilTheOperatorsFileChanges) {
  const auto operator_yaml = config.yaml();
  const auto kept = keep_remote(operator_yaml);
  daemon = std::make_unique<Daemon>(dir, operator_yaml);
  const auto before = file_seen(daemon->config_path());
  expect_remote_serves();
  EXPECT_NE(daemon->log().find("remote config 1 (cli, by integrator, at " + kept.applied_at + ") is in force in place of " +
                               daemon->config_path().string()),
            std::string::npos)
      << daemon->log();

  daemon->signal(SIGHUP);
  ASSERT_TRUE(eventually([&] { return daemon->log_count("bridge: reloaded") == 1; })) << daemon->log();
  expect_remote_serves();
  EXPECT_EQ(daemon->log_count("is in force in place of"), 2u) << daemon->log();
  EXPECT_TRUE(file_seen(daemon->config_path()) == before) << "the daemon wrote the operator's file";

  // The operator edits the file: at the next SIGHUP the file wins.
  daemon->rewrite_config(operator_yaml + "# edited by the operator\n");
  daemon->signal(SIGHUP);
  ASSERT_TRUE(eventually([&] { return daemon->log_count("bridge: reloaded") == 2; })) << daemon->log();
  EXPECT_EQ(daemon->log_count("remote config: " + daemon->config_path().string() +
                              " changed since remote config 1 was applied (by integrator, at " + kept.applied_at +
                              "); the file is in force"),
            1u)
      << daemon->log();
  expect_file_serves();
  const auto edited = file_seen(daemon->config_path());

  // The file stays in force after a restart (the store was told), even on the same bytes.
  ASSERT_TRUE(daemon->terminate());
  daemon = std::make_unique<Daemon>(dir, operator_yaml + "# edited by the operator\n");
  expect_file_serves();
  EXPECT_EQ(daemon->log_count("is in force in place of"), 0u) << daemon->log();
  EXPECT_EQ(file_seen(daemon->config_path()).bytes, edited.bytes);
}

TEST_F(ConfigInForce, TheRemoteConfigStaysAfterARestartUntilTheFileChanged) {
  const auto operator_yaml = config.yaml();
  keep_remote(operator_yaml);
  daemon = std::make_unique<Daemon>(dir, operator_yaml);
  const auto before = file_seen(daemon->config_path());
  expect_remote_serves();
  ASSERT_TRUE(daemon->terminate());
  EXPECT_TRUE(file_seen(daemon->config_path()) == before) << "the daemon wrote the operator's file";

  // The same bytes again (the harness writes them anew): the remote config is still in force.
  daemon = std::make_unique<Daemon>(dir, operator_yaml);
  expect_remote_serves();
  ASSERT_TRUE(daemon->terminate());

  // Started on a changed file: the file wins, and the log says so.
  auto edited = config;
  edited.banks = "{ D1: 0x0011, W: 0x0100 }  # the same layout, written anew";
  daemon = std::make_unique<Daemon>(dir, edited.yaml());
  expect_file_serves();
  EXPECT_TRUE(daemon->wait_for_log("changed since remote config 1 was applied")) << daemon->log();
}

TEST_F(ConfigInForce, AKeptConfigThatNoLongerLoadsGivesWayToTheFile) {
  const auto operator_yaml = config.yaml();
  const auto kept = keep_remote(operator_yaml);
  test_support::write_file(kept.text_path, remote.yaml() + "modbus_typo: 1\n");
  daemon = std::make_unique<Daemon>(dir, operator_yaml);
  expect_file_serves();
  EXPECT_TRUE(daemon->wait_for_log("remote config: remote config 1 no longer loads; the file " +
                                   daemon->config_path().string() + " is in force: " + kept.text_path.string() + ":"))
      << daemon->log();
}

}  // namespace
}  // namespace unima::test
