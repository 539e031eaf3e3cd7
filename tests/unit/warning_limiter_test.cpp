// Per-peer warnings (SPEC §10, issue 17 item 4): the first of a kind from a host is logged,
// then how many more came, once a minute; a host that falls quiet is logged in full again;
// a crowd of hosts cannot flood the log either; and nothing a peer sends forges a line.

#include <gtest/gtest.h>

#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <memory>
#include <sstream>
#include <string>

#include "platform/peer_warnings.hpp"
#include "platform/warning_limiter.hpp"

namespace unima::platform {

void PrintTo(const WarningLimiter::Held& h, std::ostream* out) {
  *out << "{" << h.group << ", " << h.key << ", " << h.count << "}";
}

namespace {

using namespace std::chrono_literals;
using Clock = WarningLimiter::Clock;
using Held = WarningLimiter::Held;

const Clock::time_point t0{1h};


TEST(WarningLimiter, TheFirstIsLoggedThenACountEveryPeriod) {
  WarningLimiter limiter;
  EXPECT_FALSE(limiter.period_end());
  EXPECT_TRUE(limiter.admit("bad MBAP", "10.0.0.5", t0));
  EXPECT_EQ(limiter.period_end(), t0 + 1min);
  for (int i = 1; i <= 37; ++i) EXPECT_FALSE(limiter.admit("bad MBAP", "10.0.0.5", t0 + i * 1s));
  EXPECT_TRUE(limiter.end_period(t0 + 59s).empty());  // not over yet
  EXPECT_EQ(limiter.end_period(t0 + 1min), (std::vector<Held>{{"bad MBAP", "10.0.0.5", 37}}));
  // Still counted in the next period, not logged again.
  EXPECT_FALSE(limiter.admit("bad MBAP", "10.0.0.5", t0 + 61s));
  EXPECT_EQ(limiter.period_end(), t0 + 2min);
  EXPECT_EQ(limiter.end_period(t0 + 2min), (std::vector<Held>{{"bad MBAP", "10.0.0.5", 1}}));
  // A quiet period: forgotten, nothing left to wake for, and the next one is logged.
  EXPECT_TRUE(limiter.end_period(t0 + 3min).empty());
  EXPECT_FALSE(limiter.period_end());
  EXPECT_TRUE(limiter.admit("bad MBAP", "10.0.0.5", t0 + 5min));
}

TEST(WarningLimiter, HostsAndKindsAreCountedApart) {
  WarningLimiter limiter;
  EXPECT_TRUE(limiter.admit("bad MBAP", "10.0.0.5", t0));
  EXPECT_TRUE(limiter.admit("bad MBAP", "10.0.0.6", t0 + 1s));
  EXPECT_TRUE(limiter.admit("malformed", "10.0.0.5", t0 + 2s));
  EXPECT_FALSE(limiter.admit("bad MBAP", "10.0.0.6", t0 + 3s));
  EXPECT_FALSE(limiter.admit("malformed", "10.0.0.5", t0 + 4s));
  EXPECT_FALSE(limiter.admit("malformed", "10.0.0.5", t0 + 5s));
  EXPECT_EQ(limiter.end_period(t0 + 1min), (std::vector<Held>{{"bad MBAP", "10.0.0.6", 1}, {"malformed", "10.0.0.5", 2}}));
}

TEST(WarningLimiter, ACrowdOfHostsIsCountedTogether) {
  WarningLimiter limiter({1min, 3});
  int logged = 0;
  for (int host = 0; host < 1000; ++host) logged += limiter.admit("bad MBAP", "10.0." + std::to_string(host), t0);
  EXPECT_EQ(logged, 3);
  EXPECT_EQ(limiter.end_period(t0 + 1min), (std::vector<Held>{{"bad MBAP", "", 997}}));
  EXPECT_TRUE(limiter.admit("bad MBAP", "10.1.0.0", t0 + 61s));  // the crowd takes no place of its own
}

TEST(WarningLimiter, ALateReportKeepsThePeriodsInStep) {
  WarningLimiter limiter;
  EXPECT_TRUE(limiter.admit("k", "a", t0));
  EXPECT_FALSE(limiter.admit("k", "a", t0 + 1s));
  EXPECT_EQ(limiter.end_period(t0 + 150s).size(), 1u);
  EXPECT_EQ(limiter.period_end(), t0 + 3min);
}

TEST(PeerHost, IsTheAddressWithoutThePort) {
  EXPECT_EQ(peer_host("10.0.0.5:50123"), "10.0.0.5");
  EXPECT_EQ(peer_host("::1:50123"), "::1");
  EXPECT_EQ(peer_host("[fd00::7]:502"), "fd00::7");
  EXPECT_EQ(peer_host("unix:/run/unima-bridge/feed.sock"), "unix:/run/unima-bridge/feed.sock");
  EXPECT_EQ(peer_host("?"), "?");
}

// The warnings as they reach the log.
class PeerWarningsLog : public ::testing::Test {
 protected:
  void SetUp() override {
    previous_ = spdlog::default_logger();
    auto logger = std::make_shared<spdlog::logger>("test", std::make_shared<spdlog::sinks::ostream_sink_st>(out_));
    logger->set_pattern("%l %v");
    spdlog::set_default_logger(logger);
  }
  void TearDown() override { spdlog::set_default_logger(previous_); }
  std::string text() const { return out_.str(); }

  std::ostringstream out_;
  std::shared_ptr<spdlog::logger> previous_;
};

TEST_F(PeerWarningsLog, FiftyBadConnectionsGiveOneLineAndACount) {
  PeerWarnings warnings;
  int opened = 0;
  warnings.on_period_opened([&] { ++opened; });
  for (int i = 0; i < 50; ++i)
    warnings.warn("modbus tcp: bad MBAP headers", "10.0.0.5:" + std::to_string(40000 + i),
                  "modbus tcp: 10.0.0.5:" + std::to_string(40000 + i) + " sent a bad MBAP header", t0 + i * 100ms);
  EXPECT_EQ(text(), "warning modbus tcp: 10.0.0.5:40000 sent a bad MBAP header\n");
  EXPECT_EQ(opened, 1);
  EXPECT_EQ(warnings.next_report(), t0 + 1min);
  warnings.report(t0 + 1min);
  EXPECT_EQ(text(), "warning modbus tcp: 10.0.0.5:40000 sent a bad MBAP header\n"
                    "warning modbus tcp: bad MBAP headers from 10.0.0.5: 49 more in the last 60 s\n");
}

TEST_F(PeerWarningsLog, AReportThatWasDueIsLoggedBeforeTheNextWarning) {
  PeerWarnings warnings;  // no timer: the counts still come out
  warnings.warn("feed: malformed lines", "10.0.0.5:1", "first", t0);
  warnings.warn("feed: malformed lines", "10.0.0.5:2", "second", t0 + 1s);
  warnings.warn("feed: malformed lines", "10.0.0.5:3", "third", t0 + 3min);
  EXPECT_EQ(text(), "warning first\n"
                    "warning feed: malformed lines from 10.0.0.5: 1 more in the last 60 s\n");
}

TEST_F(PeerWarningsLog, NothingAPeerSendsCanForgeALine) {
  PeerWarnings warnings;
  warnings.warn("feed: malformed lines", "10.0.0.5:1", "feed: bad key 'a\n2024-01-01 info forged\r\x1b[2J'", t0);
  EXPECT_EQ(text(), "warning feed: bad key 'a\\n2024-01-01 info forged\\r\\x1B[2J'\n");
}

}  // namespace
}  // namespace unima::platform
