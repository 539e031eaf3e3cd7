// The MQTT history buffer's pure side (SPEC §15): the journal's lines and what a crash or
// damage makes of them, which entries go when it is full, and the window of history in
// flight after a reconnect.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "mqtt/history_journal.hpp"
#include "mqtt/history_window.hpp"

namespace unima::mqtt {
namespace {

using Status = LoadedHistory::Status;

const HistoryEntry first{1, "D1", R"({"time":"2026-11-24T20:48:09.927231Z","online":true,"engine_speed":845})"};
const HistoryEntry second{2, "C", R"({"time":"2026-11-24T20:48:10.027117Z","online":true,"name":"a b  c"})"};
const HistoryEntry third{3, "D1", R"({"time":"2026-11-24T20:48:10.127004Z","online":false,"engine_speed":null})"};

std::string journal(const std::vector<std::string>& lines) {
  std::string bytes(history_header);
  for (const auto& line : lines) bytes += line;
  return bytes;
}

TEST(MqttHistoryJournal, AnEntryIsALineWithItsDocumentAsPublishedAndAChecksum) {
  const auto line = encode_history_entry(first);
  EXPECT_TRUE(line.starts_with(R"(E 1 D1 {"time":"2026-11-24T20:48:09.927231Z",)")) << line;
  EXPECT_EQ(line.back(), '\n');
  EXPECT_EQ(line.size(), std::string("E 1 D1 ").size() + first.document.size() + 1 + 8 + 1);
  EXPECT_EQ(parse_history_entry(line), first);
  EXPECT_EQ(parse_history_entry(encode_history_entry(second)), second) << "spaces inside the document";
  auto flipped = line;
  flipped[20] ^= 0x01;
  EXPECT_FALSE(parse_history_entry(flipped));
  EXPECT_FALSE(parse_history_entry(encode_history_acknowledged(1)));
  EXPECT_EQ(encode_history_acknowledged(7).substr(0, 4), "A 7 ");
}

TEST(MqttHistoryJournal, WhatIsAcknowledgedIsNotPendingAndPlacesAreWhereTheLinesAre) {
  const auto a = encode_history_entry(first), b = encode_history_entry(second), c = encode_history_entry(third);
  const auto bytes = journal({a, b, encode_history_acknowledged(1), c});
  const auto loaded = parse_history(bytes);
  EXPECT_EQ(loaded.status, Status::ok) << loaded.problem;
  EXPECT_EQ(loaded.last_sequence, 3u);
  EXPECT_EQ(loaded.good_bytes, bytes.size());
  ASSERT_EQ(loaded.pending.size(), 2u);
  EXPECT_EQ(loaded.pending[0], (HistoryPlace{2, history_header.size() + a.size(), b.size()}));
  EXPECT_EQ(bytes.substr(loaded.pending[1].offset, loaded.pending[1].size), c);
  EXPECT_TRUE(parse_history(journal({a, b, encode_history_acknowledged(2)})).pending.empty());
  EXPECT_EQ(parse_history("").status, Status::ok);
  EXPECT_EQ(parse_history(history_header).status, Status::ok);
}

// Cut at every byte (a crash during any append): the entries before the cut line are kept,
// the cut line is dropped, nothing is ever called damage.
TEST(MqttHistoryJournal, ACutAnywhereIsATornTailThatKeepsTheWholeLinesBeforeIt) {
  const auto a = encode_history_entry(first), b = encode_history_entry(second);
  const auto bytes = journal({a, b});
  for (std::size_t cut = 1; cut < bytes.size(); ++cut) {
    const auto loaded = parse_history(std::string_view(bytes).substr(0, cut));
    ASSERT_NE(loaded.status, Status::damaged) << cut;
    ASSERT_NE(loaded.status, Status::foreign) << cut;
    const std::size_t whole = cut >= history_header.size() + a.size() ? 1 : 0;
    EXPECT_EQ(loaded.pending.size(), whole) << cut;
    EXPECT_EQ(loaded.good_bytes, cut < history_header.size() ? 0 : history_header.size() + whole * a.size()) << cut;
    if (cut != history_header.size() && cut != history_header.size() + a.size()) {
      EXPECT_EQ(loaded.status, Status::torn_tail) << cut;
    }
  }
}

TEST(MqttHistoryJournal, ABadLineBeforeTheLastIsDamageAndAnotherFileIsForeign) {
  auto a = encode_history_entry(first);
  a[10] = '#';
  const auto damaged = parse_history(journal({a, encode_history_entry(second)}));
  EXPECT_EQ(damaged.status, Status::damaged);
  EXPECT_EQ(damaged.problem, "line 2: checksum mismatch");
  EXPECT_TRUE(damaged.pending.empty());
  const auto backwards = parse_history(journal({encode_history_entry(second), encode_history_entry(first), encode_history_entry(third)}));
  EXPECT_EQ(backwards.status, Status::damaged);
  EXPECT_EQ(backwards.problem, "line 3: sequence 1 after 2");
  EXPECT_EQ(parse_history("unima-bridge state 1\nW 3 1234 8c7f0b1e\n").status, Status::foreign);
  EXPECT_EQ(parse_history("unima-bridge mqtt history 2\n").problem, "line 1: another version of the history buffer");
  EXPECT_EQ(parse_history("unima-bridge mqtt hi").status, Status::torn_tail);
}

// The bank is the topic level the entry is sent under: one that is no bank of the bridge
// ("D1/x", "#") is no entry of ours, with a good checksum and on the last line too — the
// file is damaged, not sent under a topic the bridge never owns (issue 43, finding 13).
TEST(MqttHistoryJournal, AnEntryForNoBankOfTheBridgeIsDamage) {
  for (const std::string bank : {"D1/x", "#", "+", "D9", "W/../status"}) {
    const auto loaded = parse_history(journal({encode_history_entry(first), encode_history_entry({2, bank, first.document})}));
    EXPECT_EQ(loaded.status, Status::damaged) << bank;
    EXPECT_EQ(loaded.problem, "line 3: not a bank of the bridge") << bank;
    EXPECT_FALSE(parse_history_entry(encode_history_entry({2, bank, first.document}))) << bank;
  }
}

TEST(MqttHistoryJournal, WhenFullTheOldestGoUntilAnEighthIsFree) {
  const std::vector<std::uint64_t> sizes{100, 100, 100, 100, 100, 100, 100, 100};
  EXPECT_EQ(oldest_to_drop(sizes, 800), 0u);
  EXPECT_EQ(oldest_to_drop(sizes, 1000), 0u);
  // 800 bytes in 799 of room: the rest must leave 799 / 8 (99) free, 700 bytes: one goes.
  EXPECT_EQ(oldest_to_drop(sizes, 799), 1u);
  EXPECT_EQ(oldest_to_drop(sizes, 798), 2u);
  EXPECT_EQ(oldest_to_drop(sizes, 400), 5u);  // 300 ≤ 350
  EXPECT_EQ(oldest_to_drop(sizes, 50), 8u) << "an entry larger than the room goes too";
  EXPECT_EQ(oldest_to_drop({}, 0), 0u);
}

// Issue 43, finding 11: a buffer whose room one bank document nearly fills (8 KiB, a D1
// document of 7.6 KB) dropped every entry, for no entry fits within the eighth left free;
// the newest that fit the room stay.
TEST(MqttHistoryJournal, ABufferThatOneEntryNearlyFillsKeepsTheNewest) {
  const std::vector<std::uint64_t> d1_documents{7640, 7640, 7640, 7640, 7640};
  EXPECT_EQ(oldest_to_drop(d1_documents, 8164), 4u);
  const std::vector<std::uint64_t> c_then_d1{1030, 7640};
  EXPECT_EQ(oldest_to_drop(c_then_d1, 8164), 1u) << "the newest fits the room, not within the eighth";
  const std::vector<std::uint64_t> mixed{7640, 1030, 7640, 1030};
  EXPECT_EQ(oldest_to_drop(mixed, 8164), 3u) << "within the eighth where the target keeps any";
  EXPECT_EQ(oldest_to_drop(mixed, 16356), 1u);
  EXPECT_EQ(oldest_to_drop(std::vector<std::uint64_t>{9000}, 8164), 1u) << "one larger than the room cannot stay";
}

TEST(MqttHistoryWindow, AtMostAHundredInFlightAndDeliveredUpToTheOldestUnacknowledged) {
  HistoryWindow window(10);
  EXPECT_EQ(window.room(), 100u);
  EXPECT_EQ(window.sent_up_to(), 10u);
  for (int i = 0; i < 100; ++i) window.sent(11 + static_cast<std::uint64_t>(i), 1 + i);
  EXPECT_EQ(window.room(), 0u);
  EXPECT_EQ(window.sent_up_to(), 110u);
  EXPECT_FALSE(window.acknowledged(2)) << "11 is still unacknowledged";
  EXPECT_FALSE(window.acknowledged(2)) << "twice is once";
  EXPECT_EQ(window.acknowledged(1), 12u);
  EXPECT_EQ(window.room(), 2u);
  EXPECT_FALSE(window.acknowledged(999));
  EXPECT_EQ(window.acknowledged(3), 13u);
  EXPECT_EQ(window.delivered(), 13u);
  EXPECT_EQ(window.acknowledged_total(), 3u);
}

// A connection lost with history in flight: the next one sends again from the first entry
// not acknowledged (duplicates possible, nothing lost), whatever the gaps of dropped entries.
TEST(MqttHistoryWindow, ANewConnectionResendsWhatWasInFlight) {
  HistoryWindow window(0);
  window.sent(4, 1);
  window.sent(9, 2);
  window.sent(10, 3);
  EXPECT_EQ(window.acknowledged(1), 4u);
  EXPECT_FALSE(window.acknowledged(3));
  window.restart();
  EXPECT_EQ(window.in_flight(), 0u);
  EXPECT_EQ(window.sent_up_to(), 4u);
  window.sent(9, 1);
  EXPECT_EQ(window.acknowledged(1), 9u);
}

}  // namespace
}  // namespace unima::mqtt
