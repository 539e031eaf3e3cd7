// How often an NCMD rebirth is carried out (sparkplug/rebirth_pacing; issue 43, finding 8).

#include <gtest/gtest.h>

#include "sparkplug/rebirth_pacing.hpp"

namespace unima::sparkplug {
namespace {

using namespace std::chrono_literals;
using Verdict = RebirthPacing::Verdict;

const RebirthPacing::Clock::time_point t0{100s};

TEST(SparkplugRebirthPacing, TheFirstIsAtOnceAndABurstIsOneMoreRebirthCounted) {
  RebirthPacing pacing;
  EXPECT_EQ(pacing.asked(t0), Verdict::now);
  EXPECT_EQ(pacing.asked(t0 + 1s), Verdict::later);
  EXPECT_EQ(pacing.due_at(), t0 + RebirthPacing::min_interval);
  for (int i = 0; i < 498; ++i) EXPECT_EQ(pacing.asked(t0 + 2s), Verdict::joined);
  EXPECT_EQ(pacing.coalesced(), 499u);
  pacing.done(pacing.due_at());
  // Right after the deferred one: deferred again, from that one.
  EXPECT_EQ(pacing.asked(t0 + 6s), Verdict::later);
  EXPECT_EQ(pacing.due_at(), t0 + RebirthPacing::min_interval + RebirthPacing::min_interval);
}

TEST(SparkplugRebirthPacing, RequestsFartherApartThanTheIntervalAreEachAtOnce) {
  RebirthPacing pacing;
  for (int i = 0; i < 5; ++i) EXPECT_EQ(pacing.asked(t0 + i * RebirthPacing::min_interval), Verdict::now) << i;
  EXPECT_EQ(pacing.coalesced(), 0u);
}

}  // namespace
}  // namespace unima::sparkplug
