// Whether a unit behind the gateway answers (SPEC §14, docs/gateway.md "Seen and counted"):
// three failed transactions in a row make it "not answering" since the first of them; an
// answer, its exception too, makes it answer again; and the wait statistic beside it.

#include <gtest/gtest.h>

#include "master/unit_answering.hpp"
#include "master/wait_time.hpp"

namespace unima::master {
namespace {

using namespace std::chrono_literals;
using Transition = UnitAnswering::Transition;

const UnitAnswering::Time t0 = UnitAnswering::Time{} + 1'000'000s;

TEST(UnitAnswering, AnswersUntilThreeFailuresInARowThenSinceTheFirst) {
  UnitAnswering unit;
  EXPECT_TRUE(unit.answering());
  EXPECT_FALSE(unit.silent_since());
  EXPECT_EQ(unit.failed(t0), Transition::none);
  EXPECT_EQ(unit.failed(t0 + 1s), Transition::none);
  EXPECT_TRUE(unit.answering());
  EXPECT_EQ(unit.failed(t0 + 2s), Transition::stopped_answering);
  EXPECT_FALSE(unit.answering());
  EXPECT_EQ(unit.silent_since(), t0);
  // Further failures are the same silence: no second transition, the same since.
  EXPECT_EQ(unit.failed(t0 + 3s), Transition::none);
  EXPECT_EQ(unit.silent_since(), t0);
}

TEST(UnitAnswering, AnAnswerBetweenFailuresStartsTheCountAgain) {
  UnitAnswering unit;
  unit.failed(t0);
  unit.failed(t0 + 1s);
  EXPECT_EQ(unit.answered(), Transition::none);
  EXPECT_EQ(unit.failed(t0 + 2s), Transition::none);
  EXPECT_EQ(unit.failed(t0 + 3s), Transition::none);
  EXPECT_TRUE(unit.answering());
  EXPECT_EQ(unit.failed(t0 + 4s), Transition::stopped_answering);
  EXPECT_EQ(unit.silent_since(), t0 + 2s);
}

TEST(UnitAnswering, TheFirstAnswerAfterSilenceAnswersAgainOnce) {
  UnitAnswering unit;
  for (int i = 0; i < 3; ++i) unit.failed(t0 + std::chrono::seconds(i));
  EXPECT_EQ(unit.answered(), Transition::answers_again);
  EXPECT_TRUE(unit.answering());
  EXPECT_FALSE(unit.silent_since());
  EXPECT_EQ(unit.answered(), Transition::none);
  // A new silence has its own since.
  for (int i = 10; i < 12; ++i) EXPECT_EQ(unit.failed(t0 + std::chrono::seconds(i)), Transition::none);
  EXPECT_EQ(unit.failed(t0 + 12s), Transition::stopped_answering);
  EXPECT_EQ(unit.silent_since(), t0 + 10s);
}

TEST(WaitTime, KeepsTheLastTheMeanAndTheLongest) {
  WaitTime wait;
  EXPECT_EQ(wait.count(), 0u);
  EXPECT_EQ(wait.mean(), WaitTime::Duration::zero());
  wait.took_line(10ms);
  wait.took_line(40ms);
  wait.took_line(4ms);
  EXPECT_EQ(wait.count(), 3u);
  EXPECT_EQ(wait.last(), 4ms);
  EXPECT_EQ(wait.max(), 40ms);
  EXPECT_EQ(wait.sum(), 54ms);
  EXPECT_EQ(wait.mean(), 18ms);
}

TEST(WaitTime, ANegativeWaitCountsAsNone) {
  WaitTime wait;
  wait.took_line(-1ms);
  EXPECT_EQ(wait.count(), 1u);
  EXPECT_EQ(wait.last(), WaitTime::Duration::zero());
  EXPECT_EQ(wait.sum(), WaitTime::Duration::zero());
}

}  // namespace
}  // namespace unima::master
