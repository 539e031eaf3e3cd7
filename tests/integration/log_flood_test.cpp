// Logs cannot be flooded or forged from outside (SPEC §10, issue 17 item 4): a peer that
// opens connection after connection with bad MBAP headers or malformed feed lines gets
// its first warning logged, the rest counted once a minute; text it sends is escaped. Its
// connects are limited alike (issue 29 row 6, outside_text_test.cpp).

#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <sstream>
#include <thread>

#include "io/peer_warning_reports.hpp"
#include "tests/integration/bridge_fixture.hpp"

namespace unima::test {
namespace {

using LogFlood = BridgeTest;

TEST_F(LogFlood, FiftyBadMbapConnectionsGiveOneWarning) {
  start();
  for (int i = 0; i < 50; ++i) {
    auto bad = Socket::tcp(config.modbus_port);
    bad.send(Bytes{0x00, 0x01, 0x00, 0x05, 0x00, 0x06, 0x01, 0x04, 0x00, 0x11, 0x00, 0x01});  // protocol id 5
    ASSERT_TRUE(bad.closed_by_peer()) << i;  // each loses its connection, as before
  }
  ModbusClient good(config.modbus_port);
  EXPECT_TRUE(good.read_input(0x0011, 1));
  EXPECT_EQ(daemon->log_count("sent a bad MBAP header"), 1u) << daemon->log();
  EXPECT_TRUE(daemon->running());
}

TEST_F(LogFlood, AFeedClientReconnectingWithForgedLinesGivesOneEscapedWarning) {
  start();
  for (int i = 0; i < 20; ++i) {
    auto feed = feed_client();
    feed.send(std::string("{\"a\\nFORGED log line\":1}\n"));  // a JSON key holding a newline
    const auto answer = feed.read_line();
    ASSERT_TRUE(answer) << daemon->log();
    EXPECT_TRUE(answer->starts_with(R"({"error":)")) << *answer;  // every line is still answered
  }
  EXPECT_EQ(daemon->log_count("sent a malformed line"), 1u) << daemon->log();
  EXPECT_EQ(daemon->log_count(" connected"), 1u) << daemon->log();  // its connects are limited too
  EXPECT_EQ(daemon->log().find("\nFORGED"), std::string::npos) << daemon->log();
  EXPECT_NE(daemon->log().find("a\\nFORGED"), std::string::npos) << daemon->log();
}

// The count comes out when the period ends, without another warning to carry it: the
// daemon's timer (a short period here, a minute in the daemon).
TEST(PeerWarningReports, TheCountIsLoggedWhenThePeriodEnds) {
  std::ostringstream out;
  auto logger = std::make_shared<spdlog::logger>("test", std::make_shared<spdlog::sinks::ostream_sink_st>(out));
  logger->set_pattern("%v");
  const auto previous = spdlog::default_logger();
  spdlog::set_default_logger(logger);

  asio::io_context io;
  platform::PeerWarnings warnings({std::chrono::milliseconds(200), 100});
  io::PeerWarningReports reports(io.get_executor(), warnings);
  for (int i = 0; i < 5; ++i)
    warnings.warn("modbus tcp: bad MBAP headers", "10.0.0.5:4000" + std::to_string(i), "bad header",
                  platform::PeerWarnings::Clock::now());
  io.run_for(std::chrono::milliseconds(700));
  spdlog::set_default_logger(previous);
  EXPECT_EQ(out.str(), "bad header\nmodbus tcp: bad MBAP headers from 10.0.0.5: 4 more in the last 0.2 s\n");
  EXPECT_FALSE(warnings.next_report());  // a quiet period ends the counting: nothing left to wake for
}

// What a peer does by coming and going is noted at info, limited the same way, and its
// count comes at info too; a warning's kind keeps warning.
TEST(PeerWarningReports, NotedLinesAndTheirCountsAreInfo) {
  std::ostringstream out;
  auto logger = std::make_shared<spdlog::logger>("test", std::make_shared<spdlog::sinks::ostream_sink_st>(out));
  logger->set_pattern("%l %v");
  const auto previous = spdlog::default_logger();
  spdlog::set_default_logger(logger);

  platform::PeerWarnings warnings({std::chrono::milliseconds(200), 100});
  const auto start = platform::PeerWarnings::Clock::now();
  for (int i = 0; i < 3; ++i) {
    warnings.note("feed: connections", "10.0.0.5:4000" + std::to_string(i), "connected", start);
    warnings.warn("feed: malformed lines", "10.0.0.5:4000" + std::to_string(i), "malformed", start);
  }
  warnings.report(start + std::chrono::milliseconds(200));
  spdlog::set_default_logger(previous);
  EXPECT_EQ(out.str(),
            "info connected\nwarning malformed\n"
            "info feed: connections from 10.0.0.5: 2 more in the last 0.2 s\n"
            "warning feed: malformed lines from 10.0.0.5: 2 more in the last 0.2 s\n");
}

}  // namespace
}  // namespace unima::test
