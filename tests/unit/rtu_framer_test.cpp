// The RTU framer and the frame-length rules: frames by length and by silence, streams
// split at every position, re-synchronisation after bad CRCs and garbage, and the
// query/response state of a shared bus. Times are arguments; no clock is read.

#include <gtest/gtest.h>

#include <vector>

#include "modbus/rtu/rtu_adu.hpp"
#include "modbus/rtu/rtu_frame_length.hpp"
#include "modbus/rtu/rtu_framer.hpp"
#include "modbus/rtu/rtu_timing.hpp"
#include "tests/support/seed_frames.hpp"

namespace unima::modbus {
namespace {

using namespace std::chrono_literals;
using Bytes = std::vector<std::uint8_t>;
using Kind = RtuFrame::Kind;

Bytes adu(std::uint8_t address, const Bytes& pdu) {
  Bytes out(pdu.size() + 3);
  out.resize(write_rtu_adu(address, pdu, out));
  return out;
}
Bytes cat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

// Seed 004 §5.1, §5.2: the bridge is address 1.
const Bytes seed_read = test_support::seed::read_query;
const Bytes seed_read_response = test_support::seed::read_response;
const Bytes seed_write = test_support::seed::write_query;

TEST(RtuTiming, CharacterGapAndReplyDelay) {
  const auto t = rtu_timing(19200, false, 1);  // 10 bits: 520.8 µs
  EXPECT_EQ(t.character, 521us);
  EXPECT_EQ(t.frame_gap, 1823us);
  EXPECT_EQ(t.reply_delay, 1303us);
  const auto even = rtu_timing(9600, true, 1);  // 11 bits
  EXPECT_EQ(even.baud, 9600u);
  EXPECT_EQ(even.bits_per_character, 11u);
  EXPECT_EQ(even.character, 1146us);
  EXPECT_EQ(even.frame_gap, 4011us);
  const auto two_stop = rtu_timing(4800, false, 2);  // 11 bits
  EXPECT_EQ(two_stop.frame_gap, 8021us);
  const auto fast = rtu_timing(115200, false, 1);  // fixed above 19200 baud
  EXPECT_EQ(fast.character, 87us);
  EXPECT_EQ(fast.frame_gap, 1750us);
  EXPECT_EQ(fast.reply_delay, 1250us);
}

// What the master plans its line time with must agree with what the framer cuts.
TEST(RtuFrameLength, SizesKnownBeforeTheFrameAgreeWithTheFramesLengths) {
  EXPECT_EQ(rtu_request_size(3, 2), 8u);
  EXPECT_EQ(rtu_response_size(3, 2), 9u);                         // seed 002 §6 (1)
  EXPECT_EQ(rtu_response_size(3, 2), rtu_response_length(Bytes{0x01, 0x03, 0x04}).bytes);
  EXPECT_EQ(rtu_request_size(16, 2), 13u);                        // seed 002 §6 (4)
  EXPECT_EQ(rtu_request_size(16, 2), rtu_request_length(Bytes{0x01, 0x10, 0, 9, 0, 2, 4}).bytes);
  EXPECT_EQ(rtu_response_size(16, 2), 8u);
  EXPECT_EQ(rtu_response_size(1, 9), 7u);                         // two bytes of coils
  EXPECT_EQ(rtu_response_size(1, 9), rtu_response_length(Bytes{0x01, 0x01, 0x02}).bytes);
  EXPECT_EQ(rtu_request_size(15, 9), 11u);
  EXPECT_EQ(rtu_response_size(6, 1), 8u);
}

TEST(RtuFrameLength, RequestsOfEveryFunctionWithALength) {
  using K = RtuFrameLength::Kind;
  auto length = [](const Bytes& b) { return rtu_request_length(b); };
  EXPECT_EQ(length({0x01}).kind, K::need_more);
  for (std::uint8_t fn : {1, 2, 3, 4, 5, 6}) EXPECT_EQ(length({0x01, fn}).bytes, 8u) << int(fn);
  EXPECT_EQ(length({0x01, 0x10, 0x00, 0x00, 0x00, 0x02}).kind, K::need_more);
  EXPECT_EQ(length({0x01, 0x10, 0x00, 0x00, 0x00, 0x02, 0x04}).bytes, 13u);
  EXPECT_EQ(length({0x01, 0x0F, 0x00, 0x00, 0x00, 0x0A, 0x02}).bytes, 11u);
  EXPECT_EQ(length({0x01, 0x2B, 0x0E}).bytes, 7u);
  EXPECT_EQ(length({0x01, 0x2B, 0x0D}).kind, K::unknown);  // CANopen: only silence tells
  EXPECT_EQ(length({0x01, 0x08}).kind, K::unknown);
  EXPECT_EQ(length({0x01, 0x00}).kind, K::impossible);
  EXPECT_EQ(length({0x01, 0x84}).kind, K::impossible);   // exceptions are never requests
  EXPECT_EQ(length({0x00, 0x04}).kind, K::impossible);   // a broadcast read has no one to answer it
  EXPECT_EQ(length({0x00, 0x06}).bytes, 8u);
  EXPECT_EQ(length({0x01, 0x10, 0x00, 0x00, 0x00, 0x80, 0xFF}).kind, K::impossible);  // past 256 bytes
}

TEST(RtuFrameLength, ResponsesOfEveryFunctionWithALength) {
  using K = RtuFrameLength::Kind;
  auto length = [](const Bytes& b) { return rtu_response_length(b); };
  EXPECT_EQ(length({0x01, 0x04}).kind, K::need_more);
  EXPECT_EQ(length({0x01, 0x04, 0x04}).bytes, 9u);
  EXPECT_EQ(length({0x01, 0x03, 0xFA}).bytes, 255u);  // 125 registers
  EXPECT_EQ(length({0x01, 0x01, 0x01}).bytes, 6u);
  EXPECT_EQ(length({0x01, 0x04, 0x03}).kind, K::impossible);  // registers come in pairs
  EXPECT_EQ(length({0x01, 0x04, 0x00}).kind, K::impossible);
  for (std::uint8_t fn : {5, 6, 15, 16}) EXPECT_EQ(length({0x01, fn}).bytes, 8u) << int(fn);
  EXPECT_EQ(length({0x01, 0x84}).bytes, 5u);
  EXPECT_EQ(length({0x01, 0xC1}).bytes, 5u);  // an exception of any function
  EXPECT_EQ(length({0x00, 0x04, 0x02}).kind, K::impossible);  // address 0 never answers
  EXPECT_EQ(length({0x01, 0x80}).kind, K::impossible);
  // 43/14: two objects of 3 and 0 bytes.
  const Bytes id = {0x01, 0x2B, 0x0E, 0x01, 0x81, 0x00, 0x00, 0x02, 0x00, 0x03, 'a', 'b', 'c', 0x01, 0x00};
  for (std::size_t n = 2; n < id.size(); ++n)
    EXPECT_EQ(length(Bytes(id.begin(), id.begin() + static_cast<long>(n))).kind, K::need_more) << n;
  EXPECT_EQ(length(id).bytes, id.size() + 2);
}

class Framer : public ::testing::Test {
 protected:
  static constexpr RtuClock::time_point t0{std::chrono::seconds(1000)};
  RtuFramerTiming timing = RtuFramerTiming::for_line(rtu_timing(19200, false, 1), 0ms);
  RtuFramer framer{timing, std::uint8_t{1}};

  std::vector<RtuFrame> feed(const Bytes& b, RtuClock::time_point at = t0) { return framer.feed(b, at); }
};

std::vector<Kind> kinds(const std::vector<RtuFrame>& frames) {
  std::vector<Kind> k;
  for (const auto& f : frames) k.push_back(f.kind);
  return k;
}

TEST_F(Framer, SeedQueryEndsByItsLengthWithoutWaitingForSilence) {
  const auto frames = feed(seed_read);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].kind, Kind::query);
  EXPECT_EQ(frames[0].bytes, seed_read);
  EXPECT_EQ(frames[0].end, t0);
  EXPECT_EQ(framer.deadline(), std::nullopt);
}

// SPEC §3 frame_gap: two halves of a request 5 ms apart at 19200 baud (t3.5 = 1.8 ms).
// `auto` waits t3.5 + the adapter's latency + 5 ms for the rest of a frame whose length is
// known, and joins them; an exact gap of 2 ms makes them two bad frames.
std::vector<RtuFrame> halves_5ms_apart(RtuFramer& framer) {
  constexpr RtuClock::time_point t0{std::chrono::seconds(1000)};
  const Bytes first(seed_read.begin(), seed_read.begin() + 4), second(seed_read.begin() + 4, seed_read.end());
  auto frames = framer.feed(first, t0);
  auto more = framer.tick(t0 + 5ms - 4 * 521us);  // the silence before the second half
  frames.insert(frames.end(), more.begin(), more.end());
  more = framer.feed(second, t0 + 5ms);
  frames.insert(frames.end(), more.begin(), more.end());
  more = framer.tick(t0 + 1s);
  frames.insert(frames.end(), more.begin(), more.end());
  return frames;
}

TEST(FrameGap, AutoJoinsHalvesOfARequestFiveMillisecondsApart) {
  RtuFramer framer(RtuFramerTiming::for_line(rtu_timing(19200, false, 1), 0ms), 1);
  const auto frames = halves_5ms_apart(framer);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].kind, Kind::query);
  EXPECT_EQ(frames[0].bytes, seed_read);
}

TEST(FrameGap, AnExactGapNeverJoinsThem) {
  RtuFramer framer(RtuFramerTiming::exact(rtu_timing(19200, false, 1), 2ms), 1);
  const auto frames = halves_5ms_apart(framer);
  for (const auto& f : frames) EXPECT_EQ(f.kind, Kind::bad);
  EXPECT_EQ(framer.counters().frames, 0u);
  // Each half is dropped on its own: a bad frame, or noise when shorter than any frame.
  EXPECT_GE(framer.counters().bad_frames, 1u);
  EXPECT_EQ(framer.held(), 0u);
  // A whole request right after is answered as usual.
  const auto next = framer.feed(seed_read, RtuClock::time_point{std::chrono::seconds(1002)});
  ASSERT_EQ(next.size(), 1u);
  EXPECT_EQ(next[0].kind, Kind::query);
}

TEST(FrameGap, AnExactGapIsTheSilenceThatEndsAFrameOfUnknownLength) {
  const auto timing = RtuFramerTiming::exact(rtu_timing(19200, false, 1), 3ms);
  EXPECT_EQ(timing.frame_gap, 3ms);
  EXPECT_EQ(timing.stall_timeout, 3ms);
  const auto automatic = RtuFramerTiming::for_line(rtu_timing(19200, false, 1), 16ms);
  EXPECT_EQ(automatic.stall_timeout, 1823us + 16ms + RtuFramerTiming::scheduling_margin);
}

// A bus conversation: the master reads and writes the bridge (1), reads slave 3, writes
// slave 3, gets an exception from slave 4, writes multiple registers of slave 3, and
// broadcasts a write. Every frame tells its length, so no silence is needed.
struct Conversation {
  Bytes stream;
  std::vector<Kind> kinds;
  std::vector<Bytes> frames;
  void add(Kind kind, const Bytes& frame) {
    stream.insert(stream.end(), frame.begin(), frame.end());
    kinds.push_back(kind);
    frames.push_back(frame);
  }
};

Conversation bus_conversation() {
  Conversation c;
  c.add(Kind::query, seed_read);  // the bridge's answer is not on its own input
  c.add(Kind::query, seed_write);
  c.add(Kind::query, adu(3, {0x04, 0x02, 0x00, 0x00, 0x03}));
  c.add(Kind::response, adu(3, {0x04, 0x06, 0x00, 0x01, 0x00, 0x02, 0x00, 0x03}));
  c.add(Kind::query, adu(3, {0x06, 0x02, 0x02, 0x00, 0x2A}));
  c.add(Kind::response, adu(3, {0x06, 0x02, 0x02, 0x00, 0x2A}));
  c.add(Kind::query, adu(4, {0x03, 0x00, 0x00, 0x00, 0x01}));
  c.add(Kind::response, adu(4, {0x83, 0x02}));
  c.add(Kind::query, adu(3, {0x10, 0x02, 0x00, 0x00, 0x02, 0x04, 0x12, 0x34, 0x56, 0x78}));
  c.add(Kind::response, adu(3, {0x10, 0x02, 0x00, 0x00, 0x02}));
  c.add(Kind::query, adu(0, {0x06, 0x01, 0x00, 0x00, 0x07}));
  c.add(Kind::query, adu(1, {0x2B, 0x0E, 0x01, 0x00}));
  return c;
}

TEST_F(Framer, AConversationInOneChunk) {
  const auto c = bus_conversation();
  const auto frames = feed(c.stream);
  EXPECT_EQ(kinds(frames), c.kinds);
  ASSERT_EQ(frames.size(), c.frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) EXPECT_EQ(frames[i].bytes, c.frames[i]) << i;
  EXPECT_EQ(framer.counters().frames, c.frames.size());
  EXPECT_EQ(framer.counters().bad_frames, 0u);
}

TEST(FramerSplit, AConversationSplitAtEveryPosition) {
  const auto c = bus_conversation();
  const auto timing = RtuFramerTiming::for_line(rtu_timing(19200, false, 1), 0ms);
  const RtuClock::time_point t0{std::chrono::seconds(1000)};
  for (std::size_t split = 1; split < c.stream.size(); ++split) {
    RtuFramer framer(timing, 1);
    const std::span<const std::uint8_t> all(c.stream);
    auto frames = framer.feed(all.first(split), t0);
    auto more = framer.feed(all.subspan(split), t0 + 1ms);  // less than t3.5 later
    frames.insert(frames.end(), more.begin(), more.end());
    ASSERT_EQ(kinds(frames), c.kinds) << "split at " << split;
    for (std::size_t i = 0; i < frames.size(); ++i) EXPECT_EQ(frames[i].bytes, c.frames[i]) << "split at " << split;
    EXPECT_EQ(framer.held(), 0u);
  }
}

TEST(FramerSplit, AConversationByteByByte) {
  const auto c = bus_conversation();
  RtuFramer framer(RtuFramerTiming::for_line(rtu_timing(19200, false, 1), 0ms), 1);
  RtuClock::time_point t{std::chrono::seconds(1000)};
  std::vector<RtuFrame> frames;
  for (std::uint8_t b : c.stream) {
    t += 521us;  // back to back on the wire
    auto got = framer.feed(Bytes{b}, t);
    frames.insert(frames.end(), got.begin(), got.end());
  }
  EXPECT_EQ(kinds(frames), c.kinds);
}

TEST(FramerSplit, EveryFrameSplitAtEveryPositionBehindAUsbAdapter) {
  // Bursts 16 ms apart, an FTDI's default latency timer: far more than t3.5, less than the
  // stall time-out of a line that knows its adapter's latency.
  const auto timing = RtuFramerTiming::for_line(rtu_timing(19200, false, 1), 16ms);
  const RtuClock::time_point t0{std::chrono::seconds(1000)};
  const auto c = bus_conversation();
  for (std::size_t f = 0; f < c.frames.size(); ++f) {
    const auto& frame = c.frames[f];
    for (std::size_t split = 1; split < frame.size(); ++split) {
      RtuFramer framer(timing, 1);
      // The frames before it set the expectation (query or response).
      Bytes before;
      for (std::size_t i = 0; i < f; ++i) before.insert(before.end(), c.frames[i].begin(), c.frames[i].end());
      ASSERT_EQ(framer.feed(before, t0 - 100ms).size(), f);
      const std::span<const std::uint8_t> all(frame);
      EXPECT_TRUE(framer.feed(all.first(split), t0).empty());
      EXPECT_TRUE(framer.tick(t0 + 16ms).empty());
      const auto frames = framer.feed(all.subspan(split), t0 + 16ms);
      ASSERT_EQ(frames.size(), 1u) << "frame " << f << " split at " << split;
      EXPECT_EQ(frames[0].kind, c.kinds[f]);
      EXPECT_EQ(frames[0].bytes, frame);
      EXPECT_EQ(frames[0].end, t0 + 16ms);
    }
  }
}

TEST_F(Framer, AFunctionWithoutALengthEndsAtThreeAndAHalfCharacters) {
  const auto diagnostics = adu(1, {0x08, 0x00, 0x00, 0x12, 0x34});
  EXPECT_TRUE(feed(diagnostics).empty());
  EXPECT_EQ(framer.deadline(), t0 + timing.frame_gap);
  EXPECT_TRUE(framer.tick(t0 + timing.frame_gap - 1us).empty());
  const auto frames = framer.tick(t0 + timing.frame_gap);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].kind, Kind::query);
  EXPECT_EQ(frames[0].bytes, diagnostics);
}

TEST_F(Framer, ASilenceInsideAFrameWithoutALengthWaitsForTheStallTimeOut) {
  const auto diagnostics = adu(1, {0x08, 0x00, 0x00, 0x12, 0x34});
  const std::span<const std::uint8_t> all(diagnostics);
  EXPECT_TRUE(feed(Bytes(all.begin(), all.begin() + 3)).empty());
  EXPECT_TRUE(framer.tick(t0 + timing.frame_gap).empty());  // its CRC is not there yet
  EXPECT_EQ(framer.deadline(), t0 + timing.stall_timeout);
  const auto frames = feed(Bytes(all.begin() + 3, all.end()), t0 + timing.frame_gap + 1ms);
  EXPECT_TRUE(frames.empty());
  const auto later = framer.tick(t0 + timing.frame_gap + 1ms + timing.frame_gap);
  ASSERT_EQ(later.size(), 1u);
  EXPECT_EQ(later[0].bytes, diagnostics);
}

TEST_F(Framer, ATruncatedFrameIsDroppedAfterTheStallTimeOut) {
  EXPECT_TRUE(feed({0x01, 0x04, 0x00, 0x11, 0x00}).empty());
  EXPECT_TRUE(framer.tick(t0 + timing.stall_timeout - 1us).empty());
  const auto frames = framer.tick(t0 + timing.stall_timeout);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].kind, Kind::bad);
  EXPECT_EQ(frames[0].bytes, (Bytes{0x01, 0x04, 0x00, 0x11, 0x00}));
  EXPECT_EQ(framer.counters().bad_frames, 1u);
  EXPECT_EQ(framer.held(), 0u);
  // The next frame after the silence starts afresh.
  EXPECT_EQ(kinds(feed(seed_read, t0 + 1s)), std::vector<Kind>{Kind::query});
}

TEST_F(Framer, TheRestOfATruncatedFrameAfterALongSilenceIsNotGluedToIt) {
  EXPECT_TRUE(feed({0x01, 0x04, 0x00, 0x11}).empty());
  const auto frames = feed(seed_read, t0 + 50ms);
  EXPECT_EQ(kinds(frames), (std::vector<Kind>{Kind::bad, Kind::query}));
}

TEST_F(Framer, BadCrcIsDroppedCountedAndTheNextFrameFound) {
  Bytes broken = seed_read;
  broken[7] ^= 0x01;
  const auto frames = feed(cat({broken, seed_write}));
  ASSERT_EQ(kinds(frames), (std::vector<Kind>{Kind::bad, Kind::query}));
  EXPECT_EQ(frames[0].bytes, broken);
  EXPECT_EQ(frames[1].bytes, seed_write);
  EXPECT_EQ(framer.counters().bad_frames, 1u);
}

TEST_F(Framer, ABadFrameAloneIsDroppedWholeAtTheStall) {
  Bytes broken = seed_write;
  broken[4] ^= 0x40;
  EXPECT_TRUE(feed(broken).empty());  // the next frame may be arriving behind it
  const auto frames = framer.tick(t0 + timing.stall_timeout);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].kind, Kind::bad);
  EXPECT_EQ(frames[0].bytes, broken);
}

TEST_F(Framer, GarbageBeforeAFrameIsSkipped) {
  const auto frames = feed(cat({{0x00, 0x00, 0xFF}, seed_read}));
  ASSERT_EQ(kinds(frames), std::vector<Kind>{Kind::query});
  EXPECT_EQ(frames[0].bytes, seed_read);
  EXPECT_EQ(framer.counters().skipped_bytes, 3u);
  EXPECT_EQ(framer.counters().bad_frames, 0u);
}

TEST_F(Framer, ALongRunOfGarbageNeverHoldsMoreThanAFrame) {
  Bytes garbage;
  for (int i = 0; i < 1000; ++i) garbage.push_back(static_cast<std::uint8_t>(i * 37 + 11));
  auto frames = feed(garbage);
  EXPECT_LE(framer.held(), max_rtu_adu_size + 1);
  auto more = feed(seed_read, t0 + 100ms);
  frames.insert(frames.end(), more.begin(), more.end());
  ASSERT_FALSE(frames.empty());
  EXPECT_EQ(frames.back().kind, Kind::query);
  EXPECT_EQ(frames.back().bytes, seed_read);
  for (std::size_t i = 0; i + 1 < frames.size(); ++i) EXPECT_EQ(frames[i].kind, Kind::bad);
}

TEST_F(Framer, GarbageInsideAStreamIsSkippedAtEveryPosition) {
  const auto c = bus_conversation();
  // Noise bytes that cannot start a frame between every two frames.
  for (std::size_t at = 0; at <= c.frames.size(); ++at) {
    RtuFramer fresh(timing, 1);
    Bytes stream;
    for (std::size_t i = 0; i < c.frames.size(); ++i) {
      if (i == at) stream.insert(stream.end(), {0x00, 0x00});
      stream.insert(stream.end(), c.frames[i].begin(), c.frames[i].end());
    }
    EXPECT_EQ(kinds(fresh.feed(stream, t0)), c.kinds) << "noise before frame " << at;
  }
}

TEST_F(Framer, AForeignSlavesResponseIsPairedWithItsQuery) {
  const auto query = adu(3, {0x04, 0x02, 0x00, 0x00, 0x01});
  const auto response = adu(3, {0x04, 0x02, 0x01, 0x2C});
  EXPECT_EQ(kinds(feed(cat({query, response}))), (std::vector<Kind>{Kind::query, Kind::response}));
}

TEST_F(Framer, AResponseAfterTheBridgesOwnQueryIsUnpaired) {
  // The bridge answers its own queries itself; what follows one is a query again.
  EXPECT_EQ(kinds(feed(cat({seed_read, seed_read_response}))), (std::vector<Kind>{Kind::query, Kind::unpaired_response}));
}

TEST_F(Framer, AListenerWithoutAddressExpectsAResponseAfterEveryAddressedQuery) {
  RtuFramer listener(timing, std::nullopt);
  EXPECT_EQ(kinds(listener.feed(cat({seed_read, seed_read_response}), t0)),
            (std::vector<Kind>{Kind::query, Kind::response}));
}

TEST_F(Framer, AQueryAgainWhenTheForeignSlaveIsSilentIsAQuery) {
  // Slave 3 never answers; the master asks again. Read as a response, the repeat would
  // have byte count 0x02 ≠ 2 × 1 register... the same read is a query.
  const auto query = adu(3, {0x04, 0x02, 0x00, 0x00, 0x01});
  const auto other = adu(3, {0x04, 0x00, 0x10, 0x00, 0x02});
  EXPECT_EQ(kinds(feed(cat({query, query, other}))), (std::vector<Kind>{Kind::query, Kind::query, Kind::query}));
  EXPECT_EQ(kinds(feed(adu(1, {0x04, 0x00, 0x11, 0x00, 0x02}), t0 + 1s)), std::vector<Kind>{Kind::query});
}

TEST_F(Framer, AForeignExceptionIsPaired) {
  const auto query = adu(3, {0x03, 0x00, 0x00, 0x00, 0x7D});
  EXPECT_EQ(kinds(feed(cat({query, adu(3, {0x83, 0x02})}))), (std::vector<Kind>{Kind::query, Kind::response}));
}

// Seed §5.3 note 3: the slave a foreign query asked answers another function, or fewer
// than 5 bytes: still that query's response, a faulty one (Err04).
TEST_F(Framer, AnAnswerOfAnotherFunctionIsTheQuerysFaultyResponse) {
  const auto query = adu(3, {0x04, 0x02, 0x00, 0x00, 0x01});
  const auto fn3 = adu(3, {0x03, 0x02, 0x01, 0x2C});
  auto frames = feed(cat({query, fn3}));
  ASSERT_EQ(kinds(frames), (std::vector<Kind>{Kind::query, Kind::faulty_response}));
  EXPECT_EQ(frames[1].bytes, fn3);
  // An exception of another function too; and after it the line carries a query again.
  frames = feed(cat({query, adu(3, {0x83, 0x02}), seed_read}), t0 + 1s);
  EXPECT_EQ(kinds(frames), (std::vector<Kind>{Kind::query, Kind::faulty_response, Kind::query}));
}

TEST_F(Framer, AnAnswerShorterThanFiveBytesIsTheQuerysFaultyResponseAtTheSilence) {
  const auto query = adu(3, {0x04, 0x02, 0x00, 0x00, 0x01});
  const Bytes short_answer = adu(3, {0x04});  // address, function, CRC: 4 bytes
  ASSERT_EQ(short_answer.size(), 4u);
  EXPECT_EQ(kinds(feed(cat({query, short_answer}))), std::vector<Kind>{Kind::query});
  EXPECT_TRUE(framer.tick(t0 + 1ms).empty());  // t3.5 alone does not end a frame whose length is known
  const auto frames = framer.tick(t0 + 1s);
  ASSERT_EQ(kinds(frames), std::vector<Kind>{Kind::faulty_response});
  EXPECT_EQ(frames[0].bytes, short_answer);
  // Three bytes, whatever they hold, and from the slave asked.
  feed(query, t0 + 2s);
  feed(Bytes{0x03, 0x04, 0x00}, t0 + 2s);
  EXPECT_EQ(kinds(framer.tick(t0 + 3s)), std::vector<Kind>{Kind::faulty_response});
  // From another address it is not the answer: a bad frame, as before.
  feed(query, t0 + 4s);
  feed(Bytes{0x05, 0x04, 0x00, 0x00}, t0 + 4s);
  EXPECT_EQ(kinds(framer.tick(t0 + 5s)), std::vector<Kind>{Kind::bad});
}

TEST_F(Framer, AWholeRequestToTheSameSlaveIsTheMasterMovingOnNotAFaultyResponse) {
  const auto read = adu(3, {0x04, 0x02, 0x00, 0x00, 0x01});
  const auto write = adu(3, {0x06, 0x02, 0x01, 0x00, 0x2A});  // looks like a write's response too
  EXPECT_EQ(kinds(feed(cat({read, write}))), (std::vector<Kind>{Kind::query, Kind::query}));
}

TEST_F(Framer, TheLongestResponseIsOneFrame) {
  Bytes pdu = {0x03, 250};
  for (int i = 0; i < 250; ++i) pdu.push_back(static_cast<std::uint8_t>(i));
  const auto query = adu(3, {0x03, 0x00, 0x00, 0x00, 125});
  const auto response = adu(3, pdu);
  ASSERT_EQ(response.size(), 255u);
  const auto frames = feed(cat({query, response}));
  ASSERT_EQ(kinds(frames), (std::vector<Kind>{Kind::query, Kind::response}));
  EXPECT_EQ(frames[1].bytes, response);
}

TEST_F(Framer, ABadForeignResponseIsDroppedAndTheNextQueryRead) {
  const auto query = adu(3, {0x04, 0x02, 0x00, 0x00, 0x01});
  auto response = adu(3, {0x04, 0x02, 0x01, 0x2C});
  response[4] ^= 0xFF;
  const auto frames = feed(cat({query, response, seed_read}));
  EXPECT_EQ(kinds(frames), (std::vector<Kind>{Kind::query, Kind::bad, Kind::query}));
}

TEST_F(Framer, ChunksThatArriveInOneReadDoNotCountAsSilence) {
  // 8 bytes read 4.2 ms after the first part: the wire took 8 characters to bring them.
  const std::span<const std::uint8_t> all(seed_read);
  EXPECT_TRUE(feed(Bytes(all.begin(), all.begin() + 1)).empty());
  const auto frames = feed(Bytes(all.begin() + 1, all.end()), t0 + 7 * 521us + timing.frame_gap);
  EXPECT_EQ(kinds(frames), std::vector<Kind>{Kind::query});
}

TEST_F(Framer, ResetForgetsWhatItHolds) {
  feed({0x03, 0x04, 0x02});
  framer.reset();
  EXPECT_EQ(framer.held(), 0u);
  EXPECT_EQ(framer.deadline(), std::nullopt);
  EXPECT_EQ(kinds(feed(seed_read)), std::vector<Kind>{Kind::query});
}

}  // namespace
}  // namespace unima::modbus
