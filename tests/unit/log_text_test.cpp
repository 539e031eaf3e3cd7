// Text from outside in the log (SPEC §10: logs cannot be forged from outside): log_safe
// escapes it where it is logged, and the log's formatter escapes whatever a call let
// through, so every message is one line.

#include <gtest/gtest.h>

#include <spdlog/details/log_msg.h>

#include "platform/log_text.hpp"
#include "platform/logging.hpp"

namespace unima::platform {
namespace {

TEST(LogSafe, ControlCharactersAreEscapedAndEverythingElseKept) {
  EXPECT_EQ(log_safe("66\n2026-11-27 info forged"), "66\\n2026-11-27 info forged");
  EXPECT_EQ(log_safe(std::string("a\rb\tc\x1b[2J\x7F\x01", 11)), "a\\rb\\tc\\x1B[2J\\x7F\\x01");
  EXPECT_EQ(log_safe(std::string("nul\0!", 5)), "nul\\x00!");
  EXPECT_EQ(log_safe("CN=scada 1,O=Anlage \xC3\xBC"), "CN=scada 1,O=Anlage \xC3\xBC");  // spaces and UTF-8 stay
  EXPECT_EQ(log_safe(log_safe("x\ny")), log_safe("x\ny"));  // escaping twice changes nothing more
}

std::string formatted(bool to_journal, std::string_view message) {
  const auto formatter = log_formatter(to_journal);
  const spdlog::details::log_msg msg(spdlog::source_loc{}, "test", spdlog::level::info, message);
  spdlog::memory_buf_t out;
  formatter->format(msg, out);
  return {out.data(), out.size()};
}

TEST(LogFormatter, AMessageIsOneLineWhateverItHolds) {
  for (const bool to_journal : {false, true}) {
    const auto line = formatted(to_journal, "mqtt: unima/set/W/0 = 66\n2026-11-27T00:00:00.000 info forged\r");
    EXPECT_EQ(line.find('\n'), line.size() - 1) << line;
    EXPECT_EQ(line.find('\r'), std::string::npos) << line;
    EXPECT_NE(line.find("= 66\\n2026-11-27T00:00:00.000 info forged\\r"), std::string::npos) << line;
  }
  EXPECT_EQ(formatted(true, "feed: 127.0.0.1:4000 connected"), "<6>feed: 127.0.0.1:4000 connected\n");
}

}  // namespace
}  // namespace unima::platform
