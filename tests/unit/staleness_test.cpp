// master::Staleness: a polled value goes "not measured" exactly when its block's
// stale_after passes without a good answer, once, and comes back with the next answer.

#include <gtest/gtest.h>

#include "master/staleness.hpp"

namespace unima::master {
namespace {

using namespace std::chrono_literals;
using Clock = Staleness::Clock;
using Blocks = std::vector<std::size_t>;

const Clock::time_point t0{};

TEST(Staleness, ABlockGoesStaleExactlyWhenItsLimitPassesAndOnlyOnce) {
  Staleness staleness({10s, 3s}, t0);
  EXPECT_EQ(staleness.next_expiry(), t0 + 3s);
  EXPECT_EQ(staleness.expire(t0 + 3s - 1ms), Blocks{});
  EXPECT_EQ(staleness.expire(t0 + 3s), Blocks{1});
  EXPECT_TRUE(staleness.stale(1));
  EXPECT_FALSE(staleness.stale(0));
  EXPECT_EQ(staleness.expire(t0 + 4s), Blocks{});  // reported once
  EXPECT_EQ(staleness.next_expiry(), t0 + 10s);    // a stale block no longer sets the timer
}

TEST(Staleness, AGoodAnswerRefreshesTheBlockAndPushesItsExpiryLater) {
  Staleness staleness({3s}, t0);
  staleness.refreshed(0, t0 + 2s);
  EXPECT_EQ(staleness.next_expiry(), t0 + 5s);
  EXPECT_EQ(staleness.expire(t0 + 4s), Blocks{});
  EXPECT_EQ(staleness.expire(t0 + 5s), Blocks{0});
  staleness.refreshed(0, t0 + 6s);
  EXPECT_FALSE(staleness.stale(0));
  EXPECT_EQ(staleness.next_expiry(), t0 + 9s);
}

TEST(Staleness, BlocksWithoutALimitNeverGoStale) {
  Staleness staleness({std::nullopt, 1s}, t0);
  EXPECT_EQ(staleness.expire(t0 + 1h), Blocks{1});
  EXPECT_FALSE(staleness.stale(0));
  EXPECT_EQ(staleness.next_expiry(), std::nullopt);
}

TEST(Staleness, SeveralBlocksExpiringTogetherAreReportedTogether) {
  Staleness staleness({2s, 2s, 5s}, t0);
  EXPECT_EQ(staleness.expire(t0 + 2s), (Blocks{0, 1}));
  EXPECT_EQ(staleness.expire(t0 + 5s), Blocks{2});
}

}  // namespace
}  // namespace unima::master
