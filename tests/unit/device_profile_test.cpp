// Device profiles of the foreign slaves (seeds 000, 001, 002): the compiled-in files load,
// their points say what the seeds say, and bad profile files are rejected with positions.

#include <gtest/gtest.h>

#include "master/device_profile.hpp"
#include "tests/support/error_message.hpp"

namespace unima::master {
namespace {

TEST(DeviceProfiles, AllThreeSeedsLoad) {
  ASSERT_EQ(profile_ids(), (std::vector<std::string_view>{"sic184-v2", "sic184-v3", "stepper-driver"}));
  for (const auto& p : all_profiles()) {
    EXPECT_FALSE(p.points.empty()) << p.id;
    EXPECT_EQ(p.word_order, WordOrder::low_first) << p.id;  // all three seeds: low word first
    EXPECT_FALSE(p.implements(4)) << p.id;                   // none answers function 4
  }
}

TEST(DeviceProfiles, Sic184V3) {
  const auto* p = find_profile("sic184-v3");
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->line.baud, 38400u);
  EXPECT_EQ(p->min_gap, std::chrono::milliseconds(10));  // ≤100 frames/s
  const auto* pos = p->find("POS_ACT_INT");
  ASSERT_NE(pos, nullptr);
  EXPECT_EQ(pos->reg, 1020);
  EXPECT_EQ(pos->type, ValueType::dint);
  EXPECT_EQ(pos->extent(), 2);
  EXPECT_EQ(pos->read_functions, (std::vector<std::uint8_t>{3}));
  EXPECT_TRUE(pos->write_functions.empty());
  EXPECT_EQ(pos->example, 57600);
  const auto* real = p->find("POS_ACT_REAL");
  ASSERT_NE(real, nullptr);
  EXPECT_EQ(real->reg, 1060);
  EXPECT_EQ(real->scale, 10);
  const auto* in = p->find("IN");
  ASSERT_NE(in, nullptr);
  EXPECT_EQ(in->reg, 5000);
  EXPECT_EQ(in->count, 8);
  EXPECT_TRUE(in->reads_with(2));
  const auto* out2 = p->find("OUT2");
  ASSERT_NE(out2, nullptr);
  EXPECT_EQ(out2->reg, 6001);
  EXPECT_TRUE(out2->writes_with(5));
  const auto* user = p->find("USER_REGISTER");
  ASSERT_NE(user, nullptr);
  EXPECT_EQ(user->extent(), 500);
  EXPECT_TRUE(user->writes_with(16));
}

// Seed 000 names POS_RESET 2000 in its text and 2002 in its table: the choice is recorded.
TEST(DeviceProfiles, Sic184V3PosResetRecordsTheSeedsConflict) {
  const auto* v3 = find_profile("sic184-v3");
  ASSERT_NE(v3, nullptr);
  EXPECT_EQ(v3->find("POS_RESET")->reg, 2002);
  EXPECT_NE(v3->find("POS_RESET")->inferred.find("2000"), std::string::npos);
  EXPECT_EQ(v3->find("ENABLE")->reg, 2000);
}

TEST(DeviceProfiles, Sic184V2AndStepper) {
  const auto* v2 = find_profile("sic184-v2");
  ASSERT_NE(v2, nullptr);
  EXPECT_EQ(v2->line.stop_bits, 2u);
  EXPECT_EQ(v2->frame_gap, std::chrono::microseconds(1750));
  ASSERT_NE(v2->find("XACT"), nullptr);
  EXPECT_EQ(v2->find("XACT")->reg, 10);
  EXPECT_FALSE(v2->find("IN")->inferred.empty());  // the 0xFA00 typo is recorded
  const auto* stepper = find_profile("stepper-driver");
  ASSERT_NE(stepper, nullptr);
  EXPECT_EQ(stepper->line.baud, 9600u);
  EXPECT_EQ(stepper->min_gap, std::chrono::milliseconds(35));
  EXPECT_EQ(stepper->min_reply_time, std::chrono::milliseconds(35));
  EXPECT_EQ(stepper->find("SUBDIVISION")->reg, 1);  // PLC 40002
  EXPECT_EQ(stepper->find("TEST_DISTANCE")->type, ValueType::dword);
  EXPECT_EQ(stepper->find("SINGLE_RUN")->reg, 7);   // coil 00008
  EXPECT_EQ(stepper->find("BAUD_RATE")->reg, 73);   // PLC 40074 (low) and 40075 (high)
  EXPECT_FALSE(stepper->implements(1));
}

std::string parse_error(const std::string& text) {
  return test_support::error_message<ProfileError>([&] { (void)parse_device_profile(text, "p.yaml"); });
}

TEST(DeviceProfiles, BadFilesNameTheLine) {
  const std::string head = "id: x\nfunctions: [3, 6]\npoints:\n";
  EXPECT_EQ(parse_error(head + "  - { name: A, register: 1, type: word, read: 4 }\n"),
            "p.yaml:4:47: function 4 is not in the profile's functions");
  EXPECT_EQ(parse_error(head + "  - { name: A, register: 1, type: dint, read: 3, write: 6 }\n"),
            "p.yaml:4:57: function 6 does not write dint");
  EXPECT_EQ(parse_error(head + "  - { name: A, register: 1, type: float, read: 3 }\n"),
            "p.yaml:4:35: unknown type 'float' (bits, word, int, dint, dword, real)");
  EXPECT_EQ(parse_error(head + "  - { name: A, register: 1, type: word, read: 3 }\n  - { name: A, register: 2, type: word, read: 3 }\n"),
            "p.yaml:5:5: duplicate point name 'A'");
  EXPECT_EQ(parse_error(head + "  - { name: A, register: 1, type: word, read: 3, colour: red }\n"),
            "p.yaml:4:50: unknown key 'colour' (known: name, register, type, count, length, read, write, scale, unit, "
            "label, description, inferred, example)");
}

}  // namespace
}  // namespace unima::master
