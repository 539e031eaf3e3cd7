// Where the remote configs live (io/remote_config_store, SPEC §19): numbered, kept with
// their record, the last `keep` of them and always the one in force; what cannot be read
// is skipped, never a crash; the texts are the owner's alone. Each test in a directory of
// its own.

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "io/remote_config_store.hpp"
#include "tests/support/temp_files.hpp"

namespace unima::io {
namespace {

using test_support::TempDir;
namespace fs = std::filesystem;

// 2026-11-29T22:30:05.000000Z
const auto stored_at = std::chrono::system_clock::time_point(std::chrono::seconds(1'795'991'405));

StoredConfig keep_text(RemoteConfigStore& store, const std::string& text, const std::string& by = "alice",
                       std::optional<unsigned> replaced_number = std::nullopt) {
  return store.keep(text, remote::Source::http, by, "/etc/unima-bridge/bridge.yaml", std::string(64, 'a'), replaced_number,
                    stored_at);
}

std::vector<unsigned> numbers_of(const std::vector<StoredConfig>& entries) {
  std::vector<unsigned> numbers;
  for (const auto& entry : entries) numbers.push_back(entry.number);
  return numbers;
}

unsigned mode_of(const fs::path& path) {
  struct stat st{};
  EXPECT_EQ(::stat(path.c_str(), &st), 0) << path;
  return st.st_mode & 07777;
}

config::Host host_with_state_directory(std::string state_directory) {
  config::Host host;
  host.environment = [state_directory = std::move(state_directory)](std::string_view variable) {
    return variable == "STATE_DIRECTORY" ? state_directory : std::string();
  };
  return host;
}

TEST(RemoteConfigStore, KeepsTheTextAsSentWithItsRecordAndPutsItInForce) {
  TempDir dir;
  RemoteConfigStore store(dir.path() / "remote-config", 10);
  const std::string text = "modbus: { address: 7 }\n# a password: secret";  // no final line end, kept so
  const auto stored = keep_text(store, text);
  EXPECT_EQ(stored.number, 1u);
  EXPECT_EQ(stored.id, remote::change_id(text));
  EXPECT_EQ(stored.source, remote::Source::http);
  EXPECT_EQ(stored.by, "alice");
  EXPECT_EQ(stored.applied_at, "2026-11-29T22:30:05.000000Z");
  EXPECT_EQ(stored.replaced_file, "/etc/unima-bridge/bridge.yaml");
  EXPECT_EQ(stored.replaced_sha256, std::string(64, 'a'));
  EXPECT_EQ(stored.text_path, dir.path() / "remote-config" / "000001.yaml");
  EXPECT_EQ(test_support::read_file(stored.text_path), text);
  EXPECT_EQ(store.text(stored), text);
  EXPECT_EQ(store.in_force(), stored);
  EXPECT_EQ(store.history(), std::vector<StoredConfig>{stored});
  EXPECT_TRUE(fs::is_regular_file(dir.path() / "remote-config" / "000001.json"));
}

TEST(RemoteConfigStore, EachRecordSaysWhatItReplacedTheFileOrANumber) {
  TempDir dir;
  RemoteConfigStore store(dir.path(), 10);
  const auto first = keep_text(store, "modbus: { address: 7 }\n");
  const auto second = keep_text(store, "modbus: { address: 8 }\n", "bob", first.number);
  EXPECT_EQ(first.replaced_number, std::nullopt);  // the operator's file
  EXPECT_TRUE(first.replaced_known);
  EXPECT_EQ(second.replaced_number, 1u);
  // As read back by another instance: the page's diff compares a config with the one it replaced.
  RemoteConfigStore again(dir.path(), 10);
  EXPECT_EQ(again.entry(2), second);
  EXPECT_EQ(again.entry(1), first);
  EXPECT_EQ(again.entry(3), std::nullopt);
  EXPECT_NE(test_support::read_file(dir.path() / "000001.json").find("\"replaced_number\": null"), std::string::npos);
}

TEST(RemoteConfigStore, ARecordFromBeforeReplacedNumberIsReadAndSaysItIsNotKnown) {
  TempDir dir;
  RemoteConfigStore store(dir.path(), 10);
  test_support::write_file(dir.path() / "000001.yaml", "modbus: { address: 7 }\n");
  test_support::write_file(dir.path() / "000001.json",
                           R"({"number": 1, "id": "ab", "source": "mqtt", "by": "fleet", "applied_at": "2026-11-29T22:30:05.000000Z",
                               "replaced_file": "/etc/unima-bridge/bridge.yaml", "replaced_sha256": "cd"})");
  const auto read = store.entry(1);
  ASSERT_TRUE(read.has_value());
  EXPECT_EQ(read->by, "fleet");
  EXPECT_FALSE(read->replaced_known);
  EXPECT_EQ(read->replaced_number, std::nullopt);
}

TEST(RemoteConfigStore, TheTextsAreTheOwnersAloneAndTheDirectoryToo) {
  TempDir dir;
  const auto directory = dir.path() / "state" / "remote-config";  // its parent is not there yet either
  RemoteConfigStore store(directory, 10);
  const auto old_mask = ::umask(0);  // the modes hold whatever the umask lets through
  const auto stored = keep_text(store, "log: { level: info }\n");
  ::umask(old_mask);
  EXPECT_EQ(mode_of(directory), 0700u);
  EXPECT_EQ(mode_of(stored.text_path), 0600u);
  EXPECT_EQ(mode_of(directory / "000001.json"), 0600u);
  EXPECT_EQ(mode_of(directory / "in-force.json"), 0600u);
}

TEST(RemoteConfigStore, NothingIsMadeUntilAConfigIsKept) {
  TempDir dir;
  RemoteConfigStore store(dir.path() / "remote-config", 10);
  EXPECT_FALSE(store.in_force());
  EXPECT_TRUE(store.history().empty());
  store.put_file_in_force();
  EXPECT_FALSE(fs::exists(dir.path() / "remote-config"));
}

TEST(RemoteConfigStore, NumbersGoOnAcrossInstancesNewestFirst) {
  TempDir dir;
  {
    RemoteConfigStore first(dir.path(), 10);
    keep_text(first, "log: { level: info }\n");
    keep_text(first, "log: { level: warn }\n");
  }
  RemoteConfigStore again(dir.path(), 10);
  const auto third = keep_text(again, "log: { level: error }\n", "bob");
  EXPECT_EQ(third.number, 3u);
  EXPECT_EQ(numbers_of(again.history()), (std::vector<unsigned>{3, 2, 1}));
  EXPECT_EQ(again.history().front().by, "bob");
  EXPECT_EQ(again.in_force()->number, 3u);
}

TEST(RemoteConfigStore, KeepsTheLastKeepAndForgetsTheOldest) {
  TempDir dir;
  RemoteConfigStore store(dir.path(), 2);
  for (const char* level : {"info", "warn", "error"}) keep_text(store, std::string("log: { level: ") + level + " }\n");
  EXPECT_EQ(numbers_of(store.history()), (std::vector<unsigned>{3, 2}));
  EXPECT_FALSE(fs::exists(dir.path() / "000001.yaml"));
  EXPECT_FALSE(fs::exists(dir.path() / "000001.json"));

  store.set_keep(1);  // takes effect at the next keep
  EXPECT_EQ(numbers_of(store.history()), (std::vector<unsigned>{3, 2}));
  keep_text(store, "log: { level: debug }\n");
  EXPECT_EQ(numbers_of(store.history()), (std::vector<unsigned>{4}));
}

TEST(RemoteConfigStore, TheOneInForceIsNeverForgotten) {
  TempDir dir;
  RemoteConfigStore store(dir.path(), 0);  // keep nothing: the one in force stays all the same
  keep_text(store, "log: { level: info }\n");
  const auto second = keep_text(store, "log: { level: warn }\n");
  EXPECT_EQ(store.history(), std::vector<StoredConfig>{second});
  EXPECT_EQ(store.in_force(), second);
  EXPECT_EQ(store.text(second), "log: { level: warn }\n");
}

TEST(RemoteConfigStore, PuttingTheFileInForceKeepsTheHistoryAndNoNumberComesBack) {
  TempDir dir;
  RemoteConfigStore store(dir.path(), 1);
  keep_text(store, "log: { level: info }\n");
  keep_text(store, "log: { level: warn }\n");
  store.put_file_in_force();
  EXPECT_FALSE(store.in_force());
  EXPECT_EQ(numbers_of(store.history()), (std::vector<unsigned>{2}));
  // Even with every numbered file gone (removed by hand), number 2 is not given again.
  fs::remove(dir.path() / "000002.yaml");
  fs::remove(dir.path() / "000002.json");
  EXPECT_EQ(keep_text(store, "log: { level: error }\n").number, 3u);
  EXPECT_EQ(RemoteConfigStore(dir.path(), 1).in_force()->number, 3u);
}

TEST(RemoteConfigStore, ARecordThatCannotBeReadIsSkipped) {
  TempDir dir;
  RemoteConfigStore store(dir.path(), 10);
  keep_text(store, "log: { level: info }\n");
  keep_text(store, "log: { level: warn }\n");
  keep_text(store, "log: { level: error }\n");
  test_support::write_file(dir.path() / "000001.json", "{\"number\": 1, \"id\": ");  // cut short
  fs::remove(dir.path() / "000002.yaml");                                             // its text gone
  EXPECT_EQ(numbers_of(store.history()), (std::vector<unsigned>{3}));
  EXPECT_EQ(store.in_force()->number, 3u);
  // Numbering goes on past what cannot be read.
  EXPECT_EQ(keep_text(store, "log: { level: debug }\n").number, 4u);
}

TEST(RemoteConfigStore, AnInForceRecordNamingNothingReadableMeansTheFile) {
  TempDir dir;
  RemoteConfigStore store(dir.path(), 10);
  keep_text(store, "log: { level: info }\n");
  test_support::write_file(dir.path() / "in-force.json", "{\"number\": 9, \"last_number\": 9}\n");
  EXPECT_FALSE(store.in_force());
  test_support::write_file(dir.path() / "in-force.json", "not json");
  EXPECT_FALSE(store.in_force());
  EXPECT_EQ(numbers_of(store.history()), (std::vector<unsigned>{1}));
  test_support::write_file(dir.path() / "in-force.json", "{\"number\": 1}\n");
  ASSERT_TRUE(store.in_force());
  fs::remove(dir.path() / "000001.yaml");
  EXPECT_FALSE(store.in_force());
}

TEST(RemoteConfigStore, AKeepThatCannotWriteNamesThePath) {
  TempDir dir;
  test_support::write_file(dir.path() / "not-a-directory", "");
  RemoteConfigStore store(dir.path() / "not-a-directory" / "remote-config", 10);
  try {
    keep_text(store, "log: { level: info }\n");
    FAIL() << "kept under a regular file";
  } catch (const std::system_error& e) {
    EXPECT_NE(std::string(e.what()).find((dir.path() / "not-a-directory").string()), std::string::npos) << e.what();
  }
}

TEST(RemoteConfigStoreDirectory, IsBesideTheOperatorsStateFile) {
  const auto beside = config::parse_text("", "/etc/unima-bridge/bridge.yaml", config::Host{});
  EXPECT_EQ(beside.state.file, "/etc/unima-bridge/bridge.state");
  EXPECT_EQ(RemoteConfigStore::directory_for(beside), fs::path("/etc/unima-bridge/remote-config"));

  const auto under_systemd = config::parse_text("", "/etc/unima-bridge/bridge.yaml",
                                                host_with_state_directory("/var/lib/unima-bridge:/var/lib/other"));
  EXPECT_EQ(RemoteConfigStore::directory_for(under_systemd), fs::path("/var/lib/unima-bridge/remote-config"));

  const auto named = config::parse_text("state: { file: /srv/plc/values.state }\n", "/etc/unima-bridge/bridge.yaml",
                                        host_with_state_directory("/var/lib/unima-bridge"));
  EXPECT_EQ(RemoteConfigStore::directory_for(named), fs::path("/srv/plc/remote-config"));
}

TEST(RemoteConfigStoreDirectory, IsNoneWithoutAStateFile) {
  const auto none = config::parse_text("state: { file: none }\n", "/etc/unima-bridge/bridge.yaml", config::Host{});
  EXPECT_TRUE(RemoteConfigStore::directory_for(none).empty());
}

}  // namespace
}  // namespace unima::io
