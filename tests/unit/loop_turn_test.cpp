#include "io/loop_turn.hpp"

#include <gtest/gtest.h>

#include <chrono>

using namespace std::chrono_literals;
using unima::io::loop_turn_budget;
using unima::io::SliceSize;
using unima::io::TurnDeadline;

TEST(TurnDeadline, IsSpentOnceTheBudgetSinceItsBeginningIsGone) {
  TurnDeadline turn;
  const TurnDeadline::Clock::time_point began{1s};
  turn.begin(began);
  EXPECT_FALSE(turn.spent(began));
  EXPECT_FALSE(turn.spent(began + loop_turn_budget - 1ns));
  EXPECT_TRUE(turn.spent(began + loop_turn_budget));
  turn.begin(began + 1s);  // a new turn, a new budget
  EXPECT_FALSE(turn.spent(began + 1s + loop_turn_budget / 2));
}

TEST(SliceSize, BeginsAtItsMostAndShrinksToWhatFitsTheBudget) {
  SliceSize slice(64);
  EXPECT_EQ(slice.next(), 64u);
  // 64 answers at 10 × the budget / 64 each: a tenth of them fits.
  slice.took(64, 10 * loop_turn_budget);
  EXPECT_EQ(slice.next(), 6u);
}

TEST(SliceSize, TakesAtLeastOnePieceHoweverDearAndNothingLearntFromNone) {
  SliceSize slice(64);
  slice.took(1, 100 * loop_turn_budget);
  EXPECT_EQ(slice.next(), 1u);
  slice.took(0, 0ns);  // a slice that found nothing to do says nothing of the pace
  EXPECT_EQ(slice.next(), 1u);
}

TEST(SliceSize, GrowsAtMostTwofoldASliceAndNeverPastItsMost) {
  SliceSize slice(64);
  slice.took(1, 100 * loop_turn_budget);
  ASSERT_EQ(slice.next(), 1u);
  // Cheap again (1,000 would fit): one slice the scheduler had cut short is no pace.
  slice.took(1, loop_turn_budget / 1000);
  EXPECT_EQ(slice.next(), 2u);
  slice.took(2, loop_turn_budget / 1000);
  EXPECT_EQ(slice.next(), 4u);
  for (int i = 0; i < 10; ++i) slice.took(slice.next(), loop_turn_budget / 1000);
  EXPECT_EQ(slice.next(), 64u);
}

TEST(SliceSize, AMostOfNoneStillTakesOne) {
  SliceSize slice(0);
  EXPECT_EQ(slice.next(), 1u);
  EXPECT_EQ(slice.most(), 1u);
}
