// The journal's thread (platform/journal_thread): an urgent hand-over gets a turn without
// waiting for a due time, a plain one waits for the next turn, work handed over during a
// turn is the next turn's, and stopping runs one last turn. Synchronised by promises, never
// by how long something took.

#include <gtest/gtest.h>

#include <future>
#include <utility>
#include <vector>

#include "platform/journal_thread.hpp"

namespace unima::platform {
namespace {

using namespace std::chrono_literals;

TEST(JournalThread, AnUrgentHandOverGetsATurnAndStoppingRunsALastOne) {
  JournalThread thread;
  std::vector<int> queued;
  std::vector<std::vector<int>> turns;
  std::vector<bool> last_flags;
  std::promise<void> first_turn;
  bool first = true;
  thread.start([&](bool last) {
    std::vector<int> batch;
    thread.take([&] { batch.swap(queued); });
    turns.push_back(batch);
    last_flags.push_back(last);
    if (std::exchange(first, false)) first_turn.set_value();
    return std::optional<JournalThread::Clock::time_point>();
  });
  thread.hand_over([&] { queued.push_back(1); }, true);
  first_turn.get_future().wait();  // no due time: only the urgent hand-over woke it
  thread.hand_over([&] { queued.push_back(2); }, false);  // waits for a turn: the last one
  thread.stop();
  ASSERT_EQ(turns.size(), 2u);
  EXPECT_EQ(turns[0], std::vector<int>{1});
  EXPECT_EQ(turns[1], std::vector<int>{2});
  EXPECT_EQ(last_flags, (std::vector<bool>{false, true}));
}

TEST(JournalThread, WorkHandedOverDuringATurnIsTakenByTheNext) {
  JournalThread thread;
  std::vector<int> queued;
  std::vector<std::vector<int>> turns;
  std::promise<void> in_first_turn, release_first_turn, second_turn;
  auto release = release_first_turn.get_future();
  thread.start([&](bool last) {
    std::vector<int> batch;
    thread.take([&] { batch.swap(queued); });
    turns.push_back(batch);
    if (turns.size() == 1) {
      in_first_turn.set_value();
      release.wait();
    } else if (turns.size() == 2 && !last) {
      second_turn.set_value();
    }
    return std::optional<JournalThread::Clock::time_point>();
  });
  thread.hand_over([&] { queued.push_back(1); }, true);
  in_first_turn.get_future().wait();
  // The thread is busy (a sync): both join the next turn, one batch.
  thread.hand_over([&] { queued.push_back(2); }, true);
  thread.hand_over([&] { queued.push_back(3); }, true);
  release_first_turn.set_value();
  second_turn.get_future().wait();
  thread.stop();
  ASSERT_GE(turns.size(), 2u);
  EXPECT_EQ(turns[1], (std::vector<int>{2, 3}));
}

TEST(JournalThread, ATurnComesByItselfWhenItIsDue) {
  JournalThread thread;
  std::promise<void> turned;
  bool once = false;
  thread.start(
      [&](bool last) {
        if (!last && !std::exchange(once, true)) turned.set_value();
        return std::optional(JournalThread::Clock::now() + 1h);
      },
      JournalThread::Clock::now());
  turned.get_future().wait();  // due at once, nothing handed over
  thread.stop();
  EXPECT_TRUE(once);
}

}  // namespace
}  // namespace unima::platform
