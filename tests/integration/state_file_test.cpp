// io::StateFile on a real file (SPEC §10): the order in which writes are committed and
// acknowledged, the writes kept from an acknowledgement (one master writing in a loop), a
// full journal compacted, what the destructor still writes, a write of several values kept
// whole, a batch the disk refuses: never committed, never in the file, and a big batch
// committed and answered a slice at a time.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <vector>

#include "io/state_file.hpp"
#include "tests/support/temp_files.hpp"

namespace unima::io {
namespace {

using banks::BankId;
using banks::WrittenValue;

std::uint64_t keep(StateFile& state, BankId bank, std::uint16_t offset, std::uint16_t value) {
  const std::array<WrittenValue, 1> write = {WrittenValue{bank, offset, value}};
  return state.keep(write);
}

// Only a guard against a lost wake-up hanging the test, never a measure: each test stops
// the loop itself as soon as what it waits for has happened.
constexpr auto hang_guard = std::chrono::seconds(60);

class StateFileTest : public ::testing::Test {
 protected:
  std::filesystem::path file() const { return dir.path() / "bridge.state"; }
  // Runs the loop until `done` says so; the sync thread posts to it meanwhile.
  void run_until(const std::function<bool()>& done) {
    io.restart();  // the last run ended as its work guard went: that stopped the loop
    auto guard = asio::make_work_guard(io);
    while (!done() && io.run_one_for(hang_guard) > 0) {
    }
    ASSERT_TRUE(done()) << "the loop ran out of work first";
  }
  test_support::TempDir dir;
  asio::io_context io;
};

TEST_F(StateFileTest, WritesKeptInOneTurnAreAcknowledgedInTheirOrderAndTheFileIsCompacted) {
  // 4,000 records of about 18 bytes run past the 64 KiB at which the journal is rewritten.
  constexpr std::size_t writes = 4000;
  std::vector<std::uint64_t> acknowledged;
  {
    StateFile state(io, file());
    for (std::size_t i = 0; i < writes; ++i) {
      const auto sequence = keep(state, BankId::W, static_cast<std::uint16_t>(i % 16), static_cast<std::uint16_t>(i));
      state.when_durable(sequence, [&acknowledged, sequence](bool durable) {
        EXPECT_TRUE(durable);
        acknowledged.push_back(sequence);
      });
    }
    run_until([&] { return acknowledged.size() == writes; });
    const auto counters = state.counters();
    EXPECT_EQ(counters.records, writes);
    EXPECT_GE(counters.syncs, 1u);
    EXPECT_EQ(counters.failures, 0u);
  }
  for (std::size_t i = 0; i < acknowledged.size(); ++i) ASSERT_EQ(acknowledged[i], i + 1);
  EXPECT_LT(std::filesystem::file_size(file()), 64u * 1024);
  StateFile reopened(io, file());
  for (std::size_t r = 0; r < 16; ++r)
    EXPECT_EQ(reopened.restored().w(static_cast<std::uint16_t>(r)), static_cast<std::uint16_t>(writes - 16 + r));
}

// The pattern of one master writing in a loop: each write is kept from the answer to the
// one before, when the sync thread has nothing else to do and sleeps.
TEST_F(StateFileTest, AWriteKeptFromTheAcknowledgementOfThePreviousOneIsAcknowledgedToo) {
  constexpr int writes = 200;
  int acknowledged = 0;
  StateFile state(io, file());
  std::function<void()> write_next = [&] {
    const auto sequence = keep(state, BankId::X, 0, static_cast<std::uint16_t>(acknowledged));
    state.when_durable(sequence, [&](bool durable) {
      EXPECT_TRUE(durable);
      if (++acknowledged < writes) write_next();
    });
  };
  write_next();
  run_until([&] { return acknowledged == writes; });
  EXPECT_EQ(state.counters().syncs, static_cast<std::uint64_t>(writes));  // none was there to share one
}

// A sync that holds thousands of writes (a burst of MQTT commands, issue 43 finding 6)
// commits and answers them a slice at a time, each in its own turn of the loop, so that
// whatever else the loop has to do (a Modbus request) runs between them. The turns are
// counted by a handler that posts itself again each time it runs.
TEST_F(StateFileTest, ABigBatchIsCommittedAndAnsweredASliceAtATurn) {
  constexpr std::size_t writes = 4000;
  std::size_t turn = 0;
  bool stop = false;
  std::function<void()> tick = [&] {
    ++turn;
    if (!stop) asio::post(io, tick);
  };
  asio::post(io, tick);
  std::vector<std::size_t> answered_in_turn;
  std::size_t committed = 0;
  StateFile state(io, file());
  state.set_outcome({[&](std::span<const WrittenValue>) { ++committed; }, {}});
  for (std::size_t i = 0; i < writes; ++i) {
    const auto sequence = keep(state, BankId::W, static_cast<std::uint16_t>(i % 16), static_cast<std::uint16_t>(i));
    state.when_durable(sequence, [&, sequence](bool durable) {
      EXPECT_TRUE(durable);
      EXPECT_GE(committed, sequence);  // committed before it is answered
      answered_in_turn.push_back(turn);
    });
  }
  run_until([&] { return answered_in_turn.size() == writes; });
  stop = true;
  // One turn may end a batch and begin the next (two posts the tick did not come between):
  // at most two slices. Some sync held more than that, or the test could not tell.
  const auto two_slices = 2 * StateFile::writes_per_slice;
  ASSERT_LT(state.counters().syncs, writes / two_slices);
  std::size_t most = 0;
  for (std::size_t i = 0, same = 0; i < writes; ++i) {
    same = i > 0 && answered_in_turn[i] == answered_in_turn[i - 1] ? same + 1 : 1;
    most = std::max(most, same);
  }
  EXPECT_LE(most, two_slices);
  EXPECT_GE(most, StateFile::writes_per_slice);
}

TEST_F(StateFileTest, TheDestructorWritesAndSyncsWhatWasKeptBeforeIt) {
  {
    StateFile state(io, file());
    for (std::uint16_t i = 0; i < 16; ++i) keep(state, BankId::W, i, static_cast<std::uint16_t>(100 + i));
    keep(state, BankId::W, 3, 7);
  }  // the loop never ran: nothing was acknowledged, and nothing may be lost
  StateFile reopened(io, file());
  EXPECT_EQ(reopened.restored().w(0), 100);
  EXPECT_EQ(reopened.restored().w(3), 7);
  EXPECT_EQ(reopened.restored().w(15), 115);
}

// A disk that refuses the append (here the process's file size limit, EFBIG): every write of
// that batch is refused, never acknowledged; once the disk takes writes again, the next
// batch rewrites the file and is acknowledged.
TEST_F(StateFileTest, AWriteTheDiskRefusesIsNeverAcknowledgedAndTheNextOneRepairsTheFile) {
  StateFile state(io, file());
  rlimit before{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &before), 0);
  const auto previous_handler = ::signal(SIGXFSZ, SIG_IGN);
  rlimit full = before;
  full.rlim_cur = std::filesystem::file_size(file());
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &full), 0);

  std::vector<WrittenValue> committed;
  int refusals = 0;
  state.set_outcome({[&](std::span<const WrittenValue> write) { committed.insert(committed.end(), write.begin(), write.end()); },
                     [&] { ++refusals; }});
  std::vector<bool> answers;
  for (std::uint16_t i = 0; i < 5; ++i)
    state.when_durable(keep(state, BankId::W, i, 1), [&](bool durable) { answers.push_back(durable); });
  EXPECT_EQ(state.pending(BankId::W, 4), 1);
  run_until([&] { return answers.size() == 5; });
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &before), 0);
  ::signal(SIGXFSZ, previous_handler);
  EXPECT_EQ(answers, std::vector<bool>(5, false));
  EXPECT_GE(state.counters().failures, 1u);
  EXPECT_GE(refusals, 1);
  EXPECT_TRUE(committed.empty());
  EXPECT_EQ(state.pending(BankId::W, 4), std::nullopt);  // refused: nothing pending any more

  bool repaired = false;
  state.when_durable(keep(state, BankId::W, 9, 99), [&](bool durable) {
    // Committed before it is acknowledged.
    EXPECT_EQ(committed, (std::vector<WrittenValue>{{BankId::W, 9, 99}}));
    repaired = durable;
  });
  run_until([&] { return repaired; });
  StateFile reopened(io, file());
  EXPECT_EQ(reopened.restored().w(9), 99);
  for (std::uint16_t i = 0; i < 5; ++i) EXPECT_EQ(reopened.restored().w(i), std::nullopt) << i;  // never taken
}

// The values of one write share its number and its batch: they are committed together,
// in the order of the writes, and the file holds them as one write.
TEST_F(StateFileTest, AWriteOfSeveralValuesIsKeptCommittedAndAcknowledgedAsOne) {
  std::vector<std::vector<WrittenValue>> committed;
  std::vector<std::uint64_t> acknowledged;
  {
    StateFile state(io, file());
    state.set_outcome({[&](std::span<const WrittenValue> write) { committed.emplace_back(write.begin(), write.end()); },
                       {}});
    const std::vector<WrittenValue> first = {{BankId::W, 10, 7}, {BankId::W, 11, 8}, {BankId::X, 0, 3}};
    const std::vector<WrittenValue> second = {{BankId::W, 10, 1}};
    const auto a = state.keep(first);
    const auto b = state.keep(second);
    EXPECT_EQ(a, 1u);
    EXPECT_EQ(b, 2u);
    EXPECT_EQ(state.pending(BankId::W, 10), 1);  // the latest of the two
    EXPECT_EQ(state.pending(BankId::W, 11), 8);
    EXPECT_EQ(state.pending(BankId::W, 12), std::nullopt);
    for (const auto sequence : {a, b})
      state.when_durable(sequence, [&, sequence](bool durable) {
        EXPECT_TRUE(durable);
        acknowledged.push_back(sequence);
      });
    run_until([&] { return acknowledged.size() == 2; });
    EXPECT_EQ(committed, (std::vector<std::vector<WrittenValue>>{first, second}));
    EXPECT_EQ(state.counters().records, 4u);
  }
  const auto text = test_support::read_file(file());
  EXPECT_NE(text.find("W 10 7 + "), std::string::npos) << text;
  EXPECT_NE(text.find("W 11 8 + "), std::string::npos) << text;
  EXPECT_NE(text.find("\nX 0 3 "), std::string::npos) << text;
  StateFile reopened(io, file());
  EXPECT_EQ(reopened.restored().w(10), 1);
  EXPECT_EQ(reopened.restored().w(11), 8);
  EXPECT_EQ(reopened.restored().x(), 3);
}

}  // namespace
}  // namespace unima::io
