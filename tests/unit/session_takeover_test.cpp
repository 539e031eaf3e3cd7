// When the broker gave the bridge's session to another client with its id
// (mqtt/session_takeover.hpp): MQTT 5 says so; MQTT 3.1.1 shows it as young connections the
// broker closes, one after the other.

#include <gtest/gtest.h>

#include "mqtt/session_takeover.hpp"

namespace unima::mqtt {
namespace {

using namespace std::chrono_literals;
using Clock = SessionTakeover::Clock;

class Takeover : public ::testing::Test {
 protected:
  /// A connection made at `now`, ended `after` later as `end`: whether it was taken over.
  bool connection(std::chrono::milliseconds after, ConnectionEnd end) {
    rule.connected(now);
    now += after;
    const bool taken = rule.ended(end, now);
    now += 1s;  // the back-off before the next connection
    return taken;
  }
  SessionTakeover rule;
  Clock::time_point now{};
};

TEST_F(Takeover, Mqtt5SaysSoAtOnce) {
  EXPECT_TRUE(connection(2h, ConnectionEnd::taken_over));
  EXPECT_TRUE(connection(1s, ConnectionEnd::taken_over));
}

TEST_F(Takeover, OneYoungConnectionTheBrokerClosesIsNotYetATakeover) {
  EXPECT_FALSE(connection(2s, ConnectionEnd::closed_by_broker));
  EXPECT_FALSE(connection(2h, ConnectionEnd::closed_by_broker));  // an old one: the broker went, say
  EXPECT_FALSE(connection(2s, ConnectionEnd::closed_by_broker));
}

TEST_F(Takeover, TheSecondInARowIsAndEachAfterIt) {
  EXPECT_FALSE(connection(1s, ConnectionEnd::closed_by_broker));
  EXPECT_TRUE(connection(1s, ConnectionEnd::closed_by_broker));
  // The other bridge, back after its own 30 s, takes this one's session after 30 s: still
  // young (short_session is longer than retry_after), still a takeover.
  EXPECT_TRUE(connection(SessionTakeover::retry_after, ConnectionEnd::closed_by_broker));
  EXPECT_TRUE(connection(59s, ConnectionEnd::closed_by_broker));
}

TEST_F(Takeover, AConnectionThatLastsOrEndsOtherwiseStartsTheCountAgain) {
  EXPECT_FALSE(connection(1s, ConnectionEnd::closed_by_broker));
  EXPECT_FALSE(connection(SessionTakeover::short_session, ConnectionEnd::closed_by_broker));
  EXPECT_FALSE(connection(1s, ConnectionEnd::closed_by_broker));
  EXPECT_FALSE(connection(1s, ConnectionEnd::failed));  // a keep-alive that timed out: the network
  EXPECT_FALSE(connection(1s, ConnectionEnd::closed_by_broker));
  EXPECT_TRUE(connection(1s, ConnectionEnd::closed_by_broker));
}

}  // namespace
}  // namespace unima::mqtt
