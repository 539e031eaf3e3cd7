// The state file's journal (SPEC §10): records with their checksums, the records of one
// write kept together, what a crash can leave at the end of the file (dropped whole), and
// damage anywhere else (nothing restored).

#include <cstdio>

#include <gtest/gtest.h>

#include "state/crc32.hpp"
#include "state/state_journal.hpp"

namespace unima::state {
namespace {

using Kind = PersistedValue::Kind;

std::string fmt_crc(std::string_view body) {
  char text[9];
  std::snprintf(text, sizeof text, "%08x", crc32(body));
  return text;
}

std::string journal(std::initializer_list<PersistedValue> values) {
  std::string text(journal_header);
  for (const auto& v : values) text += encode_record(v);
  return text;
}

TEST(Crc32, IsTheIeeeCrcOfZlib) {
  EXPECT_EQ(crc32("123456789"), 0xCBF43926u);  // the check value of CRC-32/ISO-HDLC
  EXPECT_EQ(crc32(""), 0u);
}

TEST(StateJournal, ARecordIsOneLineWithItsChecksum) {
  EXPECT_EQ(encode_record({Kind::w, 3, 1234}), "W 3 1234 " + fmt_crc("W 3 1234") + "\n");
}

TEST(StateJournal, RecordsReplayedInOrderGiveTheLastValueOfEachRegister) {
  const auto loaded = parse_journal(journal({{Kind::w, 3, 1234}, {Kind::x, 0, 5}, {Kind::w, 3, 99}, {Kind::output, 16, 7}}));
  EXPECT_EQ(loaded.status, LoadedJournal::Status::ok);
  EXPECT_EQ(loaded.records, 4u);
  EXPECT_EQ(loaded.image.w(3), 99);
  EXPECT_EQ(loaded.image.w(4), std::nullopt);  // unset, not 0x7FFF
  EXPECT_EQ(loaded.image.x(), 5);
  EXPECT_EQ(loaded.image.output(16), 7);
  EXPECT_EQ(loaded.image.output(1), std::nullopt);
}

TEST(StateJournal, AnEmptyFileAndAHeaderAloneHoldNothing) {
  EXPECT_EQ(parse_journal("").status, LoadedJournal::Status::ok);
  const auto header_only = parse_journal(journal_header);
  EXPECT_EQ(header_only.status, LoadedJournal::Status::ok);
  EXPECT_TRUE(header_only.image.empty());
}

TEST(StateJournal, ALastLineCutShortIsATornTailAndTheRestStays) {
  const auto whole = journal({{Kind::w, 0, 10}, {Kind::w, 1, 11}});
  for (std::size_t cut = 1; cut < encode_record({Kind::w, 2, 12}).size(); ++cut) {
    const auto text = whole + encode_record({Kind::w, 2, 12}).substr(0, cut);
    const auto loaded = parse_journal(text);
    EXPECT_EQ(loaded.status, LoadedJournal::Status::torn_tail) << cut;
    EXPECT_EQ(loaded.good_bytes, whole.size());
    EXPECT_EQ(loaded.image.w(1), 11);
    EXPECT_EQ(loaded.image.w(2), std::nullopt) << cut;
  }
}

TEST(StateJournal, ZerosACrashLeftAtTheEndAreATornTail) {
  const auto whole = journal({{Kind::w, 0, 10}});
  const auto loaded = parse_journal(whole + std::string(4096, '\0'));
  EXPECT_EQ(loaded.status, LoadedJournal::Status::torn_tail);
  EXPECT_EQ(loaded.image.w(0), 10);
}

// Row 4 of issue 29: what comes before the damage may be older than what was acknowledged
// last (200 here, then 300 after the damage); restoring it would publish an old setpoint.
TEST(StateJournal, ABadRecordAnywhereButTheLastLineIsDamageAndNothingIsKept) {
  auto text = journal({{Kind::w, 0, 10}, {Kind::w, 1, 11}, {Kind::w, 2, 12}});
  const auto second = text.find("W 1 11");
  text[second + 4] = '7';  // W 1 71: the checksum no longer matches
  const auto loaded = parse_journal(text);
  EXPECT_EQ(loaded.status, LoadedJournal::Status::damaged);
  EXPECT_EQ(loaded.problem, "line 3: checksum mismatch");
  EXPECT_TRUE(loaded.image.empty());
  EXPECT_EQ(loaded.records, 0u);
  EXPECT_EQ(loaded.good_bytes, 0u);

  const auto older_then_newer = [](const std::string& bad, bool bad_first) {
    std::string text(journal_header);
    text += encode_record({Kind::w, 0, 200});
    if (bad_first) text += bad;
    text += encode_record({Kind::w, 0, 300});
    if (!bad_first) text += bad + encode_record({Kind::x, 0, 1});
    return parse_journal(text);
  };
  for (const auto& bad : std::vector<std::string>{"garbage\n", "\n", "W 0 250 00000000\n", std::string("W 0 2\0\0 1\n", 10)})
    for (const bool bad_first : {true, false}) {
      const auto loaded = older_then_newer(bad, bad_first);
      EXPECT_EQ(loaded.status, LoadedJournal::Status::damaged) << bad << bad_first;
      EXPECT_TRUE(loaded.image.empty()) << bad << bad_first;
    }
}

TEST(StateJournal, TheRecordsOfOneWriteAreMarkedAllButTheLast) {
  EXPECT_EQ(encode_record({Kind::w, 10, 7}, true), "W 10 7 + " + fmt_crc("W 10 7 +") + "\n");
  EXPECT_EQ(encode_record({Kind::w, 12, 9}, false), encode_record({Kind::w, 12, 9}));
  const auto text = std::string(journal_header) + encode_record({Kind::w, 10, 7}, true) +
                    encode_record({Kind::w, 11, 8}, true) + encode_record({Kind::w, 12, 9}) +
                    encode_record({Kind::x, 0, 3});
  const auto loaded = parse_journal(text);
  EXPECT_EQ(loaded.status, LoadedJournal::Status::ok);
  EXPECT_EQ(loaded.records, 4u);
  EXPECT_EQ(loaded.good_bytes, text.size());
  EXPECT_EQ(loaded.image.w(10), 7);
  EXPECT_EQ(loaded.image.w(12), 9);
  EXPECT_EQ(loaded.image.x(), 3);
}

// A crash while a write of three registers was appended: whatever part of it reached the
// disk, the write is dropped whole and the writes before it stay.
TEST(StateJournal, AWriteCutShortAnywhereAtTheEndIsATornTailDroppedWhole) {
  const auto before = journal({{Kind::w, 0, 10}, {Kind::w, 10, 1}});
  const auto write = encode_record({Kind::w, 10, 7}, true) + encode_record({Kind::w, 11, 8}, true) +
                     encode_record({Kind::w, 12, 9});
  for (std::size_t cut = 1; cut < write.size(); ++cut) {
    const auto loaded = parse_journal(before + write.substr(0, cut));
    EXPECT_EQ(loaded.status, LoadedJournal::Status::torn_tail) << cut;
    EXPECT_EQ(loaded.good_bytes, before.size()) << cut;
    EXPECT_EQ(loaded.records, 2u) << cut;
    EXPECT_EQ(loaded.image.w(0), 10) << cut;
    EXPECT_EQ(loaded.image.w(10), 1) << cut;  // not 7: the torn write never happened
    EXPECT_EQ(loaded.image.w(11), std::nullopt) << cut;
    EXPECT_FALSE(loaded.problem.empty()) << cut;
  }
  EXPECT_EQ(parse_journal(before + write).status, LoadedJournal::Status::ok);
}

// A write that is not the last one but lacks its last record cannot come from a crash.
TEST(StateJournal, AWriteWhoseRecordsAreDamagedInTheMiddleIsDamage) {
  auto write = encode_record({Kind::w, 10, 7}, true) + encode_record({Kind::w, 11, 8}, true) +
               encode_record({Kind::w, 12, 9});
  write[write.find("W 11 8") + 5] = '6';
  const auto loaded = parse_journal(journal({{Kind::w, 0, 10}}) + write + encode_record({Kind::x, 0, 1}));
  EXPECT_EQ(loaded.status, LoadedJournal::Status::damaged);
  EXPECT_EQ(loaded.problem, "line 4: checksum mismatch");
  EXPECT_TRUE(loaded.image.empty());
}

TEST(StateJournal, ARecordWithAGoodChecksumButNoSuchRegisterIsRefused) {
  const std::string body = "W 16 5";  // W has 0..15
  const auto loaded = parse_journal(std::string(journal_header) + body + " " + fmt_crc(body) + "\n" +
                                    encode_record({Kind::w, 0, 1}));
  EXPECT_EQ(loaded.status, LoadedJournal::Status::damaged);
  EXPECT_EQ(loaded.problem, "line 2: bad register or value");
  for (const std::string bad : {"O 0 5", "O 17 5", "X 1 5", "W 0 65536", "Q 0 5", "W -1 5"}) {
    const auto one = parse_journal(std::string(journal_header) + bad + " " + fmt_crc(bad) + "\n" +
                                   encode_record({Kind::w, 0, 1}));
    EXPECT_EQ(one.status, LoadedJournal::Status::damaged) << bad;
  }
}

// A checksum that holds over a record that is none is no torn write, even on the last
// line: the file is damaged, and so set aside at start (issue 43, finding 13).
TEST(StateJournal, ABadRecordWithAGoodChecksumIsDamagedOnTheLastLineToo) {
  const std::string body = "W 16 5";
  const auto loaded = parse_journal(journal({{Kind::w, 0, 10}}) + body + " " + fmt_crc(body) + "\n");
  EXPECT_EQ(loaded.status, LoadedJournal::Status::damaged);
  EXPECT_EQ(loaded.problem, "line 3: bad register or value");
  EXPECT_TRUE(loaded.image.empty());
}

TEST(StateJournal, AnotherFileOrVersionIsForeignAndGivesNothing) {
  EXPECT_EQ(parse_journal("W 3 1234 00000000\n").status, LoadedJournal::Status::foreign);
  const auto other = parse_journal("unima-bridge state 2\nW 3 1234 00000000\n");
  EXPECT_EQ(other.status, LoadedJournal::Status::foreign);
  EXPECT_EQ(other.problem, "line 1: another version of the state file");
  EXPECT_TRUE(other.image.empty());
  EXPECT_EQ(parse_journal("unima-bridge st").status, LoadedJournal::Status::torn_tail);  // a new file's torn header
}

TEST(StateJournal, ACompactedImageLoadsBackAsTheSameImage) {
  StateImage image;
  image.apply({Kind::w, 15, 0x7FFF});  // written by a master: set, even at 0x7FFF
  image.apply({Kind::x, 0, 0xFFFF});
  image.apply({Kind::output, 1, 0});
  const auto loaded = parse_journal(encode_image(image));
  EXPECT_EQ(loaded.status, LoadedJournal::Status::ok);
  EXPECT_EQ(loaded.image, image);
  EXPECT_EQ(loaded.records, 3u);
}

}  // namespace
}  // namespace unima::state
