// web::connection_to_evict (issue 43, finding 7): which connection of a full HTTP server
// closes for a newcomer — never one with a request in progress; of the rest, one of the host
// holding the most connections, the one idle the longest among ties.

#include <gtest/gtest.h>

#include <vector>

#include "web/connection_eviction.hpp"

namespace unima::web {
namespace {

using namespace std::chrono_literals;

const OpenConnection::Clock::time_point t0{1h};

OpenConnection idle(std::string_view host, OpenConnection::Clock::duration since) { return {host, t0 + since, false}; }
OpenConnection busy(std::string_view host, OpenConnection::Clock::duration since) { return {host, t0 + since, true}; }

TEST(ConnectionEviction, AConnectionWithARequestInProgressIsNeverChosen) {
  // The filed daemon closed the first: a login waiting for its password check, idle the
  // longest since its request was read.
  const std::vector open{busy("127.0.0.1", 0s), idle("127.0.0.2", 5s), idle("127.0.0.3", 9s)};
  EXPECT_EQ(connection_to_evict(open), 1u);
}

TEST(ConnectionEviction, NoneWhenEveryConnectionHasARequestInProgress) {
  const std::vector open{busy("127.0.0.1", 0s), busy("127.0.0.2", 1s), busy("127.0.0.2", 2s)};
  EXPECT_EQ(connection_to_evict(open), std::nullopt);
  EXPECT_EQ(connection_to_evict({}), std::nullopt);
}

TEST(ConnectionEviction, TheHostHoldingTheMostConnectionsGivesWay) {
  // 127.0.0.1's connection is idle the longest, but 127.0.0.9 holds three.
  const std::vector open{idle("127.0.0.1", 0s), idle("127.0.0.9", 4s), idle("127.0.0.9", 2s), idle("127.0.0.9", 3s),
                         idle("127.0.0.5", 1s)};
  EXPECT_EQ(connection_to_evict(open), 2u) << "127.0.0.9's idle the longest";
}

TEST(ConnectionEviction, BusyConnectionsCountForTheirHostButOnlyAnIdleOneGoes) {
  // 127.0.0.9 holds three, two of them waiting for their answers: its idle one goes, though
  // 127.0.0.1's two have been idle longer.
  const std::vector open{idle("127.0.0.1", 0s), idle("127.0.0.1", 1s), busy("127.0.0.9", 2s), busy("127.0.0.9", 3s),
                         idle("127.0.0.9", 8s)};
  EXPECT_EQ(connection_to_evict(open), 4u);
}

TEST(ConnectionEviction, AHostWhoseConnectionsAreAllBusyLeavesTheNextHostToGiveWay) {
  const std::vector open{busy("127.0.0.9", 0s), busy("127.0.0.9", 1s), busy("127.0.0.9", 2s), idle("127.0.0.1", 5s),
                         idle("127.0.0.2", 6s), idle("127.0.0.2", 7s)};
  EXPECT_EQ(connection_to_evict(open), 4u) << "127.0.0.2 holds two, 127.0.0.1 one";
}

TEST(ConnectionEviction, AmongHostsHoldingAsManyTheLongestIdleGoes) {
  const std::vector open{idle("127.0.0.1", 6s), idle("127.0.0.2", 3s), idle("127.0.0.3", 9s), idle("127.0.0.2", 7s),
                         idle("127.0.0.1", 4s), idle("127.0.0.3", 5s)};
  EXPECT_EQ(connection_to_evict(open), 1u);
  const std::vector one_each{idle("127.0.0.1", 6s), idle("127.0.0.2", 2s), idle("127.0.0.3", 4s)};
  EXPECT_EQ(connection_to_evict(one_each), 1u);
}

}  // namespace
}  // namespace unima::web
