// tls::HandshakeLimiter (SPEC §11, issue 29 row 3): handshakes per peer host at once and
// per second, all hosts at once, and a bounded memory of hosts — with explicit time points.

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "tls/handshake_limiter.hpp"

namespace unima::tls {
namespace {

using namespace std::chrono_literals;
using Verdict = HandshakeLimiter::Verdict;
const HandshakeLimiter::Clock::time_point t0{};

TEST(HandshakeLimiter, AHostMayHaveTwoHandshakesAtOnceAndAThirdOnceOneEnds) {
  HandshakeLimiter limiter;
  EXPECT_EQ(limiter.admit("127.0.0.2", t0), Verdict::admitted);
  EXPECT_EQ(limiter.admit("127.0.0.2", t0), Verdict::admitted);
  EXPECT_EQ(limiter.admit("127.0.0.2", t0), Verdict::host_in_progress);
  EXPECT_EQ(limiter.admit("127.0.0.1", t0), Verdict::admitted) << "another host is not held by it";
  limiter.finished("127.0.0.2", true);
  EXPECT_EQ(limiter.admit("127.0.0.2", t0), Verdict::admitted);
  EXPECT_EQ(limiter.in_progress(), 3u);
  EXPECT_EQ(limiter.counters().completed, 1u);
  EXPECT_EQ(limiter.counters().refused_of(Verdict::host_in_progress), 1u);
}

TEST(HandshakeLimiter, AHostsBurstIsTwentyThenTenASecond) {
  HandshakeLimiter limiter;
  for (int i = 0; i < 20; ++i) {
    ASSERT_EQ(limiter.admit("10.0.0.9", t0), Verdict::admitted) << i;
    limiter.finished("10.0.0.9", false);
  }
  EXPECT_EQ(limiter.admit("10.0.0.9", t0), Verdict::host_rate);
  EXPECT_EQ(limiter.admit("10.0.0.9", t0 + 99ms), Verdict::host_rate);
  EXPECT_EQ(limiter.admit("10.0.0.9", t0 + 100ms), Verdict::admitted) << "one token a tenth of a second";
  limiter.finished("10.0.0.9", true);
  EXPECT_EQ(limiter.admit("10.0.0.9", t0 + 150ms), Verdict::host_rate);
  // Over a second of a steady flood, ten get through.
  int admitted = 0;
  for (auto t = t0 + 200ms; t < t0 + 1200ms; t += 10ms) {
    if (limiter.admit("10.0.0.9", t) != Verdict::admitted) continue;
    ++admitted;
    limiter.finished("10.0.0.9", false);
  }
  EXPECT_EQ(admitted, 10);
  EXPECT_EQ(limiter.counters().failed, 30u);
  EXPECT_EQ(limiter.counters().refused_of(Verdict::host_rate), 3u + 90u);
  // After a rest the whole burst is back, and no more than that.
  for (int i = 0; i < 20; ++i) {
    ASSERT_EQ(limiter.admit("10.0.0.9", t0 + 60s), Verdict::admitted) << i;
    limiter.finished("10.0.0.9", true);
  }
  EXPECT_EQ(limiter.admit("10.0.0.9", t0 + 60s), Verdict::host_rate);
}

TEST(HandshakeLimiter, AllHostsTogetherHaveAtMostTheGlobalNumberInProgress) {
  HandshakeLimiter limiter({.in_progress = 3});
  EXPECT_EQ(limiter.admit("a", t0), Verdict::admitted);
  EXPECT_EQ(limiter.admit("b", t0), Verdict::admitted);
  EXPECT_EQ(limiter.admit("c", t0), Verdict::admitted);
  EXPECT_EQ(limiter.admit("d", t0), Verdict::all_in_progress);
  limiter.finished("b", false);
  EXPECT_EQ(limiter.admit("d", t0), Verdict::admitted);
  EXPECT_EQ(limiter.counters().refused_of(Verdict::all_in_progress), 1u);
}

TEST(HandshakeLimiter, HostsAtRestAreForgottenAndBusyOnesFillNoMoreThanTheTable) {
  HandshakeLimiter limiter({.hosts = 4});
  for (const char* host : {"a", "b", "c", "d"}) {
    ASSERT_EQ(limiter.admit(host, t0), Verdict::admitted);
    limiter.finished(host, true);
  }
  // All four spent a token just now: none is at rest, so a fifth host is not told apart.
  EXPECT_EQ(limiter.admit("e", t0), Verdict::all_in_progress);
  EXPECT_EQ(limiter.hosts_remembered(), 4u);
  // A tenth of a second later their buckets are full again: they are forgotten for it.
  EXPECT_EQ(limiter.admit("e", t0 + 100ms), Verdict::admitted);
  EXPECT_EQ(limiter.hosts_remembered(), 1u);
}

TEST(HandshakeLimiter, AHostWithAHandshakeInProgressIsNotForgotten) {
  HandshakeLimiter limiter({.hosts = 1});
  ASSERT_EQ(limiter.admit("a", t0), Verdict::admitted);
  EXPECT_EQ(limiter.admit("b", t0 + 10s), Verdict::all_in_progress);
  limiter.finished("a", false);
  EXPECT_EQ(limiter.admit("b", t0 + 10s), Verdict::admitted);
}

TEST(HandshakeLimiter, ASlotCountsAFailureUnlessCompleted) {
  auto limiter = std::make_shared<HandshakeLimiter>();
  {
    ASSERT_EQ(limiter->admit("a", t0), Verdict::admitted);
    HandshakeSlot completed(limiter, "a");
    ASSERT_EQ(limiter->admit("a", t0), Verdict::admitted);
    HandshakeSlot abandoned(limiter, "a");
    EXPECT_EQ(limiter->in_progress(), 2u);
    completed.completed();
    completed.completed();  // once
    EXPECT_EQ(limiter->in_progress(), 1u);
    HandshakeSlot moved = std::move(abandoned);
    EXPECT_EQ(limiter->in_progress(), 1u);
  }
  EXPECT_EQ(limiter->in_progress(), 0u);
  EXPECT_EQ(limiter->counters().completed, 1u);
  EXPECT_EQ(limiter->counters().failed, 1u);
}

// A reload that moves the port drops its limiter while a connection still handshakes.
TEST(HandshakeLimiter, ASlotKeepsItsLimiterAlive) {
  auto limiter = std::make_shared<HandshakeLimiter>();
  ASSERT_EQ(limiter->admit("a", t0), Verdict::admitted);
  HandshakeSlot slot(limiter, "a");
  const std::weak_ptr<HandshakeLimiter> watched = limiter;
  limiter.reset();
  EXPECT_FALSE(watched.expired());
  slot = HandshakeSlot{};
  EXPECT_TRUE(watched.expired());
}

TEST(HandshakeLimiter, TheRefusalsHaveTheMetricsNames) {
  EXPECT_STREQ(HandshakeLimiter::name(Verdict::host_in_progress), "per_host_in_progress");
  EXPECT_STREQ(HandshakeLimiter::name(Verdict::host_rate), "per_host_rate");
  EXPECT_STREQ(HandshakeLimiter::name(Verdict::all_in_progress), "in_progress");
}

}  // namespace
}  // namespace unima::tls
