// A log file that cannot be written is reported once, and its recovery once (issue 17 item
// 4): a full disk whose writes alternately fail and succeed — each failed write is cut
// back, which frees a little room — is one outage, not hundreds of log lines a second.

#include <gtest/gtest.h>

#include "monitor/write_outage.hpp"

namespace unima::monitor {
namespace {

using namespace std::chrono_literals;
using Clock = WriteOutage::Clock;

const Clock::time_point t0{1h};

TEST(WriteOutage, NoOutageNoRecovery) {
  WriteOutage outage(5s);
  EXPECT_FALSE(outage.failing());
  EXPECT_FALSE(outage.succeeded(t0));
}

TEST(WriteOutage, AFullDiskThatFlapsIsOneOutageReportedOnceAndItsEndOnce) {
  WriteOutage outage(5s);
  int reported = 0;
  int recovered = 0;
  // 220 writes a second for 10 s, every other one failing.
  for (int i = 0; i < 2200; ++i) {
    const auto now = t0 + i * 1s / 220;
    if (i % 2 == 0) reported += outage.failed(now);
    else recovered += outage.succeeded(now).has_value();
  }
  EXPECT_EQ(reported, 1);
  EXPECT_EQ(recovered, 0);
  EXPECT_TRUE(outage.failing());
  const auto last_failure = t0 + 2198 * 1s / 220;
  EXPECT_FALSE(outage.succeeded(last_failure + 5s - 1ms));  // not yet settled
  const auto recovery = outage.succeeded(last_failure + 5s);
  ASSERT_TRUE(recovery);
  EXPECT_EQ(recovery->failed_writes, 1100u);
  EXPECT_EQ(recovery->lasted, last_failure - t0);
  EXPECT_FALSE(outage.failing());
  EXPECT_FALSE(outage.succeeded(last_failure + 6s));  // reported once
}

TEST(WriteOutage, AFailureAfterTheRecoveryIsANewOutage) {
  WriteOutage outage(5s);
  EXPECT_TRUE(outage.failed(t0));
  EXPECT_FALSE(outage.failed(t0 + 1s));
  ASSERT_TRUE(outage.succeeded(t0 + 60s));  // quiet for a minute: the first write that works ends it
  EXPECT_TRUE(outage.failed(t0 + 61s));
  const auto second = outage.succeeded(t0 + 70s);
  ASSERT_TRUE(second);
  EXPECT_EQ(second->failed_writes, 1u);
  EXPECT_EQ(second->lasted, 0s);
}

}  // namespace
}  // namespace unima::monitor
