// Device profiles of the foreign slaves (seeds 000, 001, 002): the compiled-in files load,
// their points say what the seeds say, and bad profile files are rejected with positions.

#include <gtest/gtest.h>

#include "master/device_profile.hpp"
#include "master/plc_operand.hpp"
#include "tests/support/error_message.hpp"

namespace unima::master {
namespace {

TEST(DeviceProfiles, AllFourSeedsLoad) {
  ASSERT_EQ(profile_ids(), (std::vector<std::string_view>{"sic184-v2", "sic184-v3", "stepper-driver", "wecon-lx5v"}));
  for (const auto& p : all_profiles()) {
    EXPECT_TRUE(!p.points.empty() || !p.operands.empty()) << p.id;
    EXPECT_EQ(p.word_order, WordOrder::low_first) << p.id;  // all four seeds: low word first
    EXPECT_FALSE(p.implements(4)) << p.id;                   // none answers function 4
  }
}

// Seed 003: the LX5V's operands as its manual writes them, translated by the profile's
// classes (X and Y in octal).
TEST(PlcOperands, TheLx5vsOperandsBecomeAddressesAndFunctions) {
  const auto* plc = find_profile("wecon-lx5v");
  ASSERT_NE(plc, nullptr);
  EXPECT_FALSE(plc->line.has_value());  // the seed gives no serial defaults
  const auto resolved = [&](std::string_view text) {
    auto r = resolve_operand(*plc, text);
    if (auto* error = std::get_if<std::string>(&r)) {
      ADD_FAILURE() << text << ": " << *error;
      return ResolvedOperand{};
    }
    return std::get<ResolvedOperand>(r);
  };
  const auto x17 = resolved("X17");
  EXPECT_EQ(x17.number, 15u);  // octal
  EXPECT_EQ(x17.reg, 0xF800 + 15);
  EXPECT_EQ(x17.operand_class->table, DataTable::discrete_inputs);
  EXPECT_EQ(x17.operand_class->read_functions, std::vector<std::uint8_t>{2});
  EXPECT_TRUE(x17.operand_class->write_functions.empty());
  const auto y10 = resolved("y10");  // any case
  EXPECT_EQ(y10.reg, 0xFC00 + 8);
  EXPECT_EQ(y10.operand_class->write_functions.front(), 5);
  EXPECT_EQ(resolved("M100").reg, 100);
  EXPECT_EQ(resolved("D200").reg, 200);
  EXPECT_EQ(resolved("D200").operand_class->read_functions.front(), 3);
  EXPECT_EQ(resolved("X1777").reg, 0xFBFF);
  EXPECT_EQ(resolved("Y1777").reg, 0xFFFF);
  EXPECT_EQ(resolved("T5").reg, 0xF005);
}

TEST(PlcOperands, AWrongOperandSaysWhy) {
  const auto* plc = find_profile("wecon-lx5v");
  ASSERT_NE(plc, nullptr);
  const auto error = [&](std::string_view text) {
    auto r = resolve_operand(*plc, text);
    return std::holds_alternative<std::string>(r) ? std::get<std::string>(r) : std::string("accepted");
  };
  EXPECT_EQ(error("X18"), "'X18': X operands are numbered in octal (X0..X7, X10..), so '18' has no 8 or 9");
  EXPECT_EQ(error("D8000"), "'D8000' is outside D's D0..D7999");
  EXPECT_EQ(error("X2000"), "'X2000' is outside X's X0..X1777");
  EXPECT_EQ(error("C200"), "'C200' is outside C's C0..C199");  // the 32-bit counters are not mapped
  EXPECT_EQ(error("Q5"), "wecon-lx5v has no operand class 'Q' (classes: X, Y, M, S, T, C, D)");
  EXPECT_EQ(error("D"), "'D' is not an operand of wecon-lx5v (write a class and a number, e.g. D200; classes: X, Y, "
                        "M, S, T, C, D)");
  EXPECT_EQ(error("D2x"), "'D2x': '2x' is not a number");
}

TEST(PlcOperands, AClassIsCheckedWhenItsProfileIsRead) {
  const auto message = test_support::error_message<ProfileError>([] {
    (void)parse_device_profile(
        "id: plc\n"
        "functions: [1, 2, 3]\n"
        "operands:\n"
        "  - { class: X, numbering: octal, range: \"0-18\", table: discrete_inputs, offset: 0, read: 2 }\n",
        "p.yaml");
  });
  EXPECT_EQ(message, "p.yaml:4:42: range '0-18' must be FIRST-LAST in octal");
  const auto wrong_function = test_support::error_message<ProfileError>([] {
    (void)parse_device_profile(
        "id: plc\n"
        "functions: [1, 2, 3]\n"
        "operands:\n"
        "  - { class: D, numbering: decimal, range: \"0-9\", table: holding_registers, offset: 0, read: 1 }\n",
        "p.yaml");
  });
  EXPECT_NE(wrong_function.find("function 1 does not read the holding_registers table"), std::string::npos)
      << wrong_function;
}

TEST(DeviceProfiles, Sic184V3) {
  const auto* p = find_profile("sic184-v3");
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->line->baud, 38400u);
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
  EXPECT_EQ(v2->line->stop_bits, 2u);
  EXPECT_EQ(v2->frame_gap, std::chrono::microseconds(1750));
  ASSERT_NE(v2->find("XACT"), nullptr);
  EXPECT_EQ(v2->find("XACT")->reg, 10);
  EXPECT_FALSE(v2->find("IN")->inferred.empty());  // the 0xFA00 typo is recorded
  const auto* stepper = find_profile("stepper-driver");
  ASSERT_NE(stepper, nullptr);
  EXPECT_EQ(stepper->line->baud, 9600u);
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
