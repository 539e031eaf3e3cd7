// The monitor file and the UnimaBUS recording are never written through a symbolic link
// (SPEC §10, issue 17 item 5): the open refuses it (O_NOFOLLOW), the loader refuses it
// naming the key, and the link's target is left as it was.

#include <gtest/gtest.h>

#include <cerrno>
#include <filesystem>
#include <string>

#include "config/config.hpp"
#include "monitor/file_appender.hpp"
#include "monitor/log_path.hpp"
#include "monitor/monitor_sinks.hpp"
#include "tests/support/error_message.hpp"
#include "tests/support/temp_files.hpp"

namespace unima::monitor {
namespace {

using test_support::read_file;
using test_support::TempDir;

class LogPath : public ::testing::Test {
 protected:
  void SetUp() override {
    test_support::write_file(target, "precious\n");
    std::filesystem::create_symlink(target, link);
  }

  TempDir dir;
  std::filesystem::path target = dir.path() / "target";
  std::string link = (dir.path() / "monitor.log").string();
};

TEST_F(LogPath, ASymbolicLinkIsRefusedAndNothingElse) {
  EXPECT_EQ(refused_log_path(link), link + " is a symbolic link; the bridge never appends to a log through one");
  EXPECT_FALSE(refused_log_path(target.string()));
  EXPECT_FALSE(refused_log_path((dir.path() / "new.log").string()));
}

TEST_F(LogPath, TheAppenderNeverFollowsOne) {
  for (const auto route : {FileAppender::Route::direct_where_possible, FileAppender::Route::page_cache}) {
    FileAppender appender(link, route, 1 << 20);
    EXPECT_FALSE(appender.is_open());
    EXPECT_EQ(errno, ELOOP);
  }
  EXPECT_EQ(read_file(target), "precious\n");
}

TEST_F(LogPath, TheSinkRefusesOneNamingItsKey) {
  EXPECT_EQ(test_support::error_message<std::runtime_error>([&] { RotatingFileSink sink(link, 4096, 2); }),
            "monitor.file: " + link + " is a symbolic link; the bridge never appends to a log through one");
  EXPECT_EQ(test_support::error_message<std::runtime_error>([&] {
              RotatingFileSink sink(link, 4096, 2, FileAppender::Route::page_cache, "unimabus record",
                                    "unimabus.record.file");
            }),
            "unimabus.record.file: " + link + " is a symbolic link; the bridge never appends to a log through one");
  EXPECT_EQ(read_file(target), "precious\n");
  EXPECT_TRUE(std::filesystem::is_symlink(link));
}

TEST_F(LogPath, TheLoaderRefusesOneNamingItsKeyAndPosition) {
  const auto error_of = [](const std::string& yaml) {
    return test_support::error_message<config::ConfigError>([&] { (void)config::load_text(yaml, "bridge.yaml"); });
  };
  EXPECT_EQ(error_of("monitor:\n  file: " + link + "\n"),
            "bridge.yaml:2:9: monitor.file: " + link + " is a symbolic link; the bridge never appends to a log through one");
  EXPECT_EQ(error_of("unimabus:\n  record: { file: " + link + " }\n"),
            "bridge.yaml:2:19: unimabus.record.file: " + link +
                " is a symbolic link; the bridge never appends to a log through one");
  EXPECT_EQ(read_file(target), "precious\n");
}

}  // namespace
}  // namespace unima::monitor
