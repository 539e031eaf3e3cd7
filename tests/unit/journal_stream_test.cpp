// How the daemon talks to journald: the JOURNAL_STREAM check and the priority prefixes.

#include <gtest/gtest.h>

#include "platform/journal_stream.hpp"

namespace unima::platform {
namespace {

TEST(JournalPriorityPrefix, FollowsSdDaemonForEveryLevel) {
  EXPECT_EQ(journal_priority_prefix(spdlog::level::critical), "<2>");  // SD_CRIT
  EXPECT_EQ(journal_priority_prefix(spdlog::level::err), "<3>");       // SD_ERR
  EXPECT_EQ(journal_priority_prefix(spdlog::level::warn), "<4>");      // SD_WARNING
  EXPECT_EQ(journal_priority_prefix(spdlog::level::info), "<6>");      // SD_INFO
  EXPECT_EQ(journal_priority_prefix(spdlog::level::debug), "<7>");     // SD_DEBUG
  EXPECT_EQ(journal_priority_prefix(spdlog::level::trace), "<7>");
  EXPECT_EQ(journal_priority_prefix(spdlog::level::off), "");
}

TEST(JournalStream, MatchesOnlyTheSameDeviceAndInode) {
  EXPECT_TRUE(is_journal_stream("64769:123456", 64769, 123456));
  EXPECT_FALSE(is_journal_stream("64769:123456", 64769, 123457));
  EXPECT_FALSE(is_journal_stream("64769:123456", 64770, 123456));
}

TEST(JournalStream, TakesDevicesAndInodesBeyond32Bits) {
  EXPECT_TRUE(is_journal_stream("18446744073709551615:4294967296", static_cast<dev_t>(18446744073709551615ULL),
                                static_cast<ino_t>(4294967296ULL)));
}

TEST(JournalStream, RejectsMalformedValues) {
  for (const char* bad : {"", ":", "1", "1:", ":1", "1:1:1", "a:1", "1:b", " 1:1", "1:1 ", "-1:1", "1;1"})
    EXPECT_FALSE(is_journal_stream(bad, 1, 1)) << '"' << bad << '"';
}

}  // namespace
}  // namespace unima::platform
