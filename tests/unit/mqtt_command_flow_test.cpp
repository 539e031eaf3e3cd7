// How many MQTT commands may wait for their answer (mqtt/command_flow.hpp, issue 43,
// finding 6): past the high-water mark the client stops reading, and reads again only
// once the backlog is down to the low-water mark.

#include <gtest/gtest.h>

#include "mqtt/command_flow.hpp"

namespace unima::mqtt {
namespace {

CommandFlow flow_of(std::size_t high, std::size_t low) { return CommandFlow({.high_water = high, .low_water = low}); }

void take(CommandFlow& flow, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) flow.taken();
}

void answer(CommandFlow& flow, std::size_t count) {
  while (count-- > 0) flow.answered();
}

TEST(CommandFlow, ReadsUpToTheHighWaterMarkAndStopsPastIt) {
  auto flow = flow_of(4, 2);
  take(flow, 4);
  EXPECT_TRUE(flow.reading());
  flow.taken();
  EXPECT_FALSE(flow.reading());
  EXPECT_EQ(flow.waiting(), 5u);
}

TEST(CommandFlow, ReadsAgainOnlyAtTheLowWaterMark) {
  auto flow = flow_of(4, 2);
  take(flow, 5);
  answer(flow, 2);  // 3 wait: above the low-water mark, still held
  EXPECT_FALSE(flow.reading());
  flow.answered();
  EXPECT_TRUE(flow.reading());
  EXPECT_EQ(flow.waiting(), 2u);
}

TEST(CommandFlow, BetweenTheMarksItKeepsWhatItDid) {
  auto flow = flow_of(4, 2);
  take(flow, 3);
  EXPECT_TRUE(flow.reading());  // rising through the gap: still reading
  take(flow, 2);
  answer(flow, 2);
  EXPECT_FALSE(flow.reading());  // falling through the gap: still held
}

TEST(CommandFlow, ACommandAnsweredAtOnceLeavesNothingWaiting) {
  auto flow = flow_of(1, 0);
  for (int i = 0; i < 100; ++i) {
    flow.taken();
    flow.answered();
  }
  EXPECT_TRUE(flow.reading());
  EXPECT_EQ(flow.waiting(), 0u);
}

TEST(CommandFlow, AnAnswerTooManyDoesNotWrapTheCount) {
  auto flow = flow_of(4, 2);
  flow.answered();
  EXPECT_EQ(flow.waiting(), 0u);
  take(flow, 4);
  EXPECT_TRUE(flow.reading());
}

TEST(CommandFlow, TheDefaultsLeaveAGap) {
  const CommandFlow flow;
  EXPECT_GT(flow.bounds().high_water, flow.bounds().low_water);
  EXPECT_GT(flow.bounds().low_water, 0u);
}

}  // namespace
}  // namespace unima::mqtt
