// The Modbus LED's frames (SPEC §8): what the bridge sends, not what it hears.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <vector>

#include "monitor/monitor.hpp"

namespace unima::monitor {
namespace {

using namespace std::chrono_literals;

const auto t0 = std::chrono::system_clock::time_point(1700000000s);
const std::vector<std::uint8_t> query = {0x03, 0x06, 0x02, 0x02, 0x00, 0x2A, 0x00, 0x00};

modbus::Transaction on_rtu(std::chrono::system_clock::time_point time, modbus::TransactionState state, bool ours) {
  return modbus::Transaction{modbus::PortKind::rtu, {}, time, state, query, query, ours};
}

TEST(MonitorLed, AnExchangeOnlyHeardIsNoFrameSent) {
  Monitor monitor{MonitorConfig{}};
  monitor.observe(on_rtu(t0, modbus::TransactionState::not_for_me, false));
  monitor.observe(on_rtu(t0, modbus::TransactionState::err04, false));  // a foreign slave's faulty answer
  EXPECT_EQ(monitor.counters(modbus::PortKind::rtu).transactions, 2u);
  EXPECT_EQ(monitor.frames_sent(), 0u);
  EXPECT_FALSE(monitor.last_frame_sent());
}

TEST(MonitorLed, TheBridgesOwnAnswersAndTheMastersQueriesAreFramesSent) {
  Monitor monitor{MonitorConfig{}};
  monitor.observe(on_rtu(t0, modbus::TransactionState::err04, true));  // its own exception 04
  monitor.frame_sent(t0 + 1s);                                         // a query of the master
  EXPECT_EQ(monitor.frames_sent(), 2u);
  EXPECT_EQ(monitor.last_frame_sent(), t0 + 1s);
}

}  // namespace
}  // namespace unima::monitor
