// web::LoginLimits (issue 29): who may start a password check, with explicit time points —
// one peer host guessing is told to wait (its own limits) while others still get in, and
// all together never queue more than `checks`.

#include <gtest/gtest.h>

#include <string>

#include "web/login_limits.hpp"

namespace unima::web {
namespace {

using namespace std::chrono_literals;
using Admission = LoginLimits::Admission;

const LoginLimits::Clock::time_point t0{1h};

TEST(LoginLimits, AHostHasOneCheckInFlightAtATime) {
  LoginLimits limits;
  EXPECT_EQ(limits.admit("127.0.0.2", t0), Admission::admitted);
  EXPECT_EQ(limits.admit("127.0.0.2", t0 + 1ms), Admission::peer_limited);
  EXPECT_EQ(limits.admit("127.0.0.1", t0 + 1ms), Admission::admitted) << "another host is not held up";
  limits.release("127.0.0.2");
  EXPECT_EQ(limits.admit("127.0.0.2", t0 + 2ms), Admission::admitted);
  EXPECT_EQ(limits.in_flight(), 2u);
}

TEST(LoginLimits, AHostHasABurstThenItsRate) {
  LoginLimits limits;  // 2 a second, a burst of 5
  auto now = t0;
  for (int i = 0; i < 5; ++i) {
    ASSERT_EQ(limits.admit("10.0.0.9", now), Admission::admitted) << i;
    limits.release("10.0.0.9");
  }
  EXPECT_EQ(limits.admit("10.0.0.9", now), Admission::peer_limited);
  EXPECT_EQ(limits.admit("10.0.0.9", now + 499ms), Admission::peer_limited);
  EXPECT_EQ(limits.admit("10.0.0.8", now), Admission::admitted) << "the bucket is the host's";
  now += 500ms;
  EXPECT_EQ(limits.admit("10.0.0.9", now), Admission::admitted);
  limits.release("10.0.0.9");
  EXPECT_EQ(limits.admit("10.0.0.9", now), Admission::peer_limited);
  // A guesser that keeps asking gets one check each 0.5 s, no more.
  int admitted = 0;
  for (int ms = 10; ms <= 10'250; ms += 10)
    if (limits.admit("10.0.0.9", now + std::chrono::milliseconds(ms)) == Admission::admitted) {
      ++admitted;
      limits.release("10.0.0.9");
    }
  EXPECT_EQ(admitted, 20);
}

TEST(LoginLimits, AllHostsTogetherHaveAtMostChecksInFlightAndARefusalCostsNoToken) {
  LoginLimits limits(LoginLimits::Options{.checks = 3});
  for (int i = 0; i < 3; ++i) EXPECT_EQ(limits.admit("10.0.0." + std::to_string(i), t0), Admission::admitted);
  EXPECT_EQ(limits.admit("10.0.0.7", t0), Admission::busy);
  EXPECT_EQ(limits.admit("10.0.0.0", t0), Admission::peer_limited) << "its own limit first: it already has one";
  limits.release("10.0.0.1");
  EXPECT_EQ(limits.in_flight(), 2u);
  // 10.0.0.7's refusals took none of its burst.
  for (int i = 0; i < 5; ++i) {
    ASSERT_EQ(limits.admit("10.0.0.7", t0), Admission::admitted) << i;
    limits.release("10.0.0.7");
  }
  EXPECT_EQ(limits.admit("10.0.0.7", t0), Admission::peer_limited);
}

TEST(LoginLimits, ARestedHostIsForgottenWhenTheTableIsFullAndABusyOneIsNot) {
  LoginLimits limits(LoginLimits::Options{.hosts = 2});
  EXPECT_EQ(limits.admit("a", t0), Admission::admitted);  // stays in flight
  EXPECT_EQ(limits.admit("b", t0), Admission::admitted);
  limits.release("b");
  EXPECT_EQ(limits.admit("c", t0 + 100ms), Admission::busy) << "b's bucket is not full yet";
  EXPECT_EQ(limits.admit("c", t0 + 200ms), Admission::busy);
  EXPECT_EQ(limits.admit("c", t0 + 3s), Admission::admitted) << "b rested: forgotten";
  EXPECT_EQ(limits.hosts_remembered(), 2u);
  limits.release("a");
  limits.release("c");
  limits.release("unknown");  // no check of its own: changes nothing
  EXPECT_EQ(limits.in_flight(), 0u);
}

}  // namespace
}  // namespace unima::web
