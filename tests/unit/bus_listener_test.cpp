// modbus::BusListener: a foreign query on a shared RTU line is paired with the response
// that follows, or given up unanswered — by the next frame or after its time — once.

#include <gtest/gtest.h>

#include <vector>

#include "modbus/rtu/bus_listener.hpp"

namespace unima::modbus {
namespace {

using namespace std::chrono_literals;
using Bytes = std::vector<std::uint8_t>;

const RtuClock::time_point t0{};
const Bytes query = {0x03, 0x04, 0x00, 0x11, 0x00, 0x01, 0x00, 0x00};
const Bytes response = {0x03, 0x04, 0x02, 0x12, 0x34, 0x00, 0x00};

TEST(BusListener, AResponsePairsWithTheQueryBeforeIt) {
  BusListener listener(1s);
  EXPECT_FALSE(listener.deadline());
  listener.heard_query(query, t0);
  EXPECT_EQ(listener.deadline(), t0 + 1s);
  const auto exchange = listener.heard_response(response);
  ASSERT_TRUE(exchange);
  EXPECT_EQ(exchange->query, query);
  EXPECT_EQ(exchange->response, response);
  EXPECT_FALSE(listener.deadline());              // nothing waits any more
  EXPECT_FALSE(listener.heard_response(response));  // a second response answers nothing
}

TEST(BusListener, AQueryIsGivenUpExactlyAtItsTimeAndOnlyOnce) {
  BusListener listener(1s);
  listener.heard_query(query, t0);
  EXPECT_FALSE(listener.expire(t0 + 1s - 1ms));
  const auto unanswered = listener.expire(t0 + 1s);
  ASSERT_TRUE(unanswered);
  EXPECT_EQ(unanswered->query, query);
  EXPECT_TRUE(unanswered->response.empty());
  EXPECT_FALSE(listener.expire(t0 + 2s));
  EXPECT_FALSE(listener.heard_response(response));  // too late: its query was given up
}

TEST(BusListener, AnythingElseOnTheLineGivesTheWaitingQueryUp) {
  BusListener listener(1s);
  EXPECT_FALSE(listener.interrupted());
  listener.heard_query(query, t0);
  const auto unanswered = listener.interrupted();
  ASSERT_TRUE(unanswered);
  EXPECT_EQ(unanswered->query, query);
  EXPECT_FALSE(listener.interrupted());
}

TEST(BusListener, ALaterQueryMovesTheDeadline) {
  BusListener listener(1s);
  listener.heard_query(query, t0);
  listener.heard_query(query, t0 + 500ms);
  EXPECT_EQ(listener.deadline(), t0 + 1500ms);
  EXPECT_FALSE(listener.expire(t0 + 1s));
}

}  // namespace
}  // namespace unima::modbus
