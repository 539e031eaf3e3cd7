// values/leading_edge (SPEC §12, §13): when a change goes north — at once after a quiet
// 100 ms, else when the 100 ms since the last update are up.

#include <gtest/gtest.h>

#include "values/leading_edge.hpp"

namespace unima::values {
namespace {

using namespace std::chrono_literals;

TEST(LeadingEdge, TheFirstChangeGoesAtOnce) {
  const LeadingEdge edge;
  const auto t0 = LeadingEdge::Clock::now();
  EXPECT_EQ(edge.when(t0), t0);
}

TEST(LeadingEdge, AChangeWithin100msWaitsUntilTheyAreUpAndOneAfterGoesAtOnce) {
  LeadingEdge edge;
  const auto t0 = LeadingEdge::Clock::now();
  edge.went(t0);
  EXPECT_EQ(edge.when(t0), t0 + 100ms);
  EXPECT_EQ(edge.when(t0 + 30ms), t0 + 100ms);
  EXPECT_EQ(edge.when(t0 + 99ms), t0 + 100ms);
  EXPECT_EQ(edge.when(t0 + 100ms), t0 + 100ms) << "100 ms since the last: the edge";
  EXPECT_EQ(edge.when(t0 + 731ms), t0 + 731ms) << "no grid: whatever the phase";
  edge.went(t0 + 731ms);
  EXPECT_EQ(edge.when(t0 + 740ms), t0 + 831ms);
}

}  // namespace
}  // namespace unima::values
