// UTC time as text (platform/utc_time): ISO 8601 with microseconds, read back exactly.

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "platform/utc_time.hpp"

namespace unima::platform {
namespace {

using namespace std::chrono;

const system_clock::time_point at =
    sys_days(year(2026) / November / 22) + hours(14) + minutes(41) + seconds(23) + microseconds(123456);
const std::string stamp = "2026-11-22T14:41:23.123456Z";

TEST(UtcTime, IsIsoWithMicroseconds) {
  EXPECT_EQ(utc_time_text(system_clock::time_point{}), "1970-01-01T00:00:00.000000Z");
  EXPECT_EQ(utc_time_text(at), stamp);
  std::string appended = "at ";
  append_utc_time(appended, at);
  EXPECT_EQ(appended, "at " + stamp);
}

TEST(UtcTime, ReadsBackWhatItWrites) {
  EXPECT_EQ(parse_utc_time(stamp), at);
  for (const auto time : {at, at + days(400) + microseconds(1), system_clock::time_point{}})
    EXPECT_EQ(parse_utc_time(utc_time_text(time)), floor<microseconds>(time));
}

TEST(UtcTime, RefusesAnythingElse) {
  for (const std::string bad : {"2026-02-30T00:00:00.000000Z", "2026-11-22T24:00:00.000000Z", "2026-11-22T14:41:23Z",
                                "2026-11-22 14:41:23.123456Z", "2026-11-22T14:41:23.123456", "2026-11-22T14:41:23.12345+Z",
                                "2026-11-22T14:-1:23.123456Z", ""})
    EXPECT_FALSE(parse_utc_time(bad)) << bad;
}

// The date and clock of the last second are kept and reused: times in the same second,
// the next one, an earlier day and back again each read as themselves.
TEST(UtcTime, EachTimeReadsAsItselfInAnyOrder) {
  const std::vector<std::pair<system_clock::time_point, std::string>> times = {
      {at, stamp},
      {at + microseconds(1), "2026-11-22T14:41:23.123457Z"},
      {at + microseconds(876544), "2026-11-22T14:41:24.000000Z"},
      {at - days(366), "2025-11-21T14:41:23.123456Z"},
      {at + microseconds(876544) + hours(10) - microseconds(1), "2026-11-23T00:41:23.999999Z"},
      {at, stamp},
      {system_clock::time_point{}, "1970-01-01T00:00:00.000000Z"},
  };
  for (const auto& [time, text] : times) EXPECT_EQ(utc_time_text(time), text);
}

}  // namespace
}  // namespace unima::platform
