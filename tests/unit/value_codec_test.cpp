// values::raw_of and values::accepted (SPEC §17, "the way back is the same model"): a value
// in its unit becomes the register that reads back as it, or is refused with the reason —
// at the edges of W's signed tenths, of an unsigned register, of a word and of bit fields.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "config/config.hpp"
#include "values/value_codec.hpp"
#include "values/value_model.hpp"

namespace unima::values {
namespace {

using banks::BankId;

class ValueCodec : public ::testing::Test {
 protected:
  ValueCodec()
      : config(config::load_text("devices:\n  D1: { type: unigen-chp, address: 5 }\n", "codec.yaml")), model(config) {}

  const ValueDef& def(BankId bank, std::string_view name) const {
    const auto& values = model.bank(bank)->values;
    const auto found = std::find_if(values.begin(), values.end(), [&](const ValueDef& d) { return d.name == name; });
    if (found == values.end()) throw std::runtime_error("no value " + std::string(name));
    return *found;
  }

  config::Config config;
  ValueModel model;
};

// The word, or the refusal as the test's failure text.
std::optional<std::uint16_t> word(const Encoded& encoded) {
  if (const auto* raw = std::get_if<std::uint16_t>(&encoded)) return *raw;
  return std::nullopt;
}
std::string refusal(const Encoded& encoded) {
  const auto* reason = std::get_if<std::string>(&encoded);
  return reason ? *reason : std::string();
}

TEST_F(ValueCodec, WTakesSignedTenthsBelowTheWordThatMeansNotMeasured) {
  const auto& w = def(BankId::W, "w_03");
  EXPECT_EQ(word(raw_of(w, 3276.6)), 0x7FFE);
  EXPECT_EQ(word(raw_of(w, -3276.8)), 0x8000);
  EXPECT_EQ(word(raw_of(w, 0)), 0);
  EXPECT_EQ(word(raw_of(w, -0.1)), 0xFFFF);
  EXPECT_EQ(word(raw_of(w, 12.5)), 125);
  EXPECT_EQ(word(raw_of(w, 0.1 + 0.2)), 3) << "a decimal's binary noise is no finer fraction";

  EXPECT_EQ(refusal(raw_of(w, 3276.7)), "w_03 = 3276.7 would be the word 0x7FFF, which reads as not measured");
  EXPECT_EQ(refusal(raw_of(w, -3276.9)), "w_03 takes -3276.8…3276.6, not -3276.9");
  EXPECT_EQ(refusal(raw_of(w, 6553.5)), "w_03 takes -3276.8…3276.6, not 6553.5") << "0xFFFF would read back as -0.1";
  EXPECT_EQ(refusal(raw_of(w, 12.34)), "w_03 takes steps of 0.1, and 12.34 is between two");
  EXPECT_EQ(refusal(raw_of(w, 12.301)), "w_03 takes steps of 0.1, and 12.301 is between two");
  EXPECT_EQ(refusal(raw_of(w, std::nan(""))), "w_03 takes a number, not nan");
  EXPECT_FALSE(word(raw_of(w, 1e300)));
}

TEST_F(ValueCodec, EveryWordWReadsAsComesBackAsThatWord) {
  const auto& w = def(BankId::W, "w_00");
  for (std::uint32_t raw = 0; raw <= 0xFFFF; ++raw) {
    const auto reading = read_word(w, static_cast<std::uint16_t>(raw));
    if (const auto* number = std::get_if<double>(&reading.reading))
      ASSERT_EQ(word(raw_of(w, *number)), raw) << *number << ": " << refusal(raw_of(w, *number));
    else
      ASSERT_EQ(raw, 0x7FFFu);
  }
}

TEST_F(ValueCodec, TheRangeAndStepAHostIsToldAreTheCodecsOwnEdges) {
  const auto w = accepted(def(BankId::W, "w_03"));
  ASSERT_TRUE(w);
  EXPECT_EQ(w->min, -3276.8);
  EXPECT_EQ(w->max, 3276.6);
  EXPECT_EQ(w->step, 0.1);
  EXPECT_TRUE(word(raw_of(def(BankId::W, "w_03"), w->min)));
  EXPECT_TRUE(word(raw_of(def(BankId::W, "w_03"), w->max)));

  const auto x = accepted(def(BankId::X, "x"));
  ASSERT_TRUE(x);
  EXPECT_EQ(x->min, 0);
  EXPECT_EQ(x->max, 65535);
  EXPECT_EQ(x->step, 1);
}

TEST_F(ValueCodec, AnUnsignedRegisterTakesItsWholeWordButTheNotMeasuredOneInTheMiddle) {
  const auto& speed = def(BankId::D1, "engine_speed");  // unsigned, scale 1
  const auto range = accepted(speed);
  ASSERT_TRUE(range);
  EXPECT_EQ(range->min, 0);
  EXPECT_EQ(range->max, 65535);
  EXPECT_EQ(word(raw_of(speed, 65535)), 0xFFFF);
  EXPECT_EQ(word(raw_of(speed, 40000)), 40000);
  EXPECT_EQ(refusal(raw_of(speed, -1)), "engine_speed takes 0…65535, not -1");
  EXPECT_EQ(refusal(raw_of(speed, 65536)), "engine_speed takes 0…65535, not 65536");
  EXPECT_EQ(refusal(raw_of(speed, 32767)), "engine_speed = 32767 would be the word 0x7FFF, which reads as not measured");
  EXPECT_EQ(refusal(raw_of(speed, 1.5)), "engine_speed takes steps of 1, and 1.5 is between two");
}

TEST_F(ValueCodec, ABitFieldIsPutIntoTheRegisterKeepingTheOtherBits) {
  const auto& power_mode = def(BankId::D1, "status.power_mode");  // bit 11
  EXPECT_EQ(word(raw_of(power_mode, 1, 0x0042)), 0x0842);
  EXPECT_EQ(word(raw_of(power_mode, 0, 0xFFFF)), 0xF7FF);
  EXPECT_EQ(refusal(raw_of(power_mode, 2, 0)), "status.power_mode takes 0…1, not 2");
  const auto& unit_mode = def(BankId::D1, "status.unit_mode");  // bits 8-10
  EXPECT_EQ(word(raw_of(unit_mode, 6, 0x0842)), 0x0E42);
  EXPECT_EQ(accepted(unit_mode)->max, 7);
}

// X's bits (x.0 … x.15) are booleans of the one word: a bit written is that bit, with the
// mask that keeps the other fifteen (the way a Sparkplug DCMD to x.N is written).
TEST_F(ValueCodec, ABitOfXIsItsBitAloneOneOrZero) {
  const auto& bit5 = def(BankId::X, "x.5");
  EXPECT_EQ(bit5.type, ValueType::boolean);
  EXPECT_EQ(word_mask(bit5), 0x0020u);
  EXPECT_EQ(word(raw_of(bit5, 1, 0x0003)), 0x0023) << "true: bit 5 set, bits 0 and 1 kept";
  EXPECT_EQ(word(raw_of(bit5, 0, 0xFFFF)), 0xFFDF) << "false: bit 5 cleared, the rest kept";
  EXPECT_EQ(word(raw_of(bit5, 1)), 0x0020);
  EXPECT_EQ(refusal(raw_of(bit5, 2)), "x.5 takes 0…1, not 2");
  EXPECT_EQ(refusal(raw_of(bit5, -1)), "x.5 takes 0…1, not -1");
  EXPECT_EQ(refusal(raw_of(bit5, 0.5)), "x.5 takes steps of 1, and 0.5 is between two");
  EXPECT_EQ(word_mask(def(BankId::X, "x.0")), 0x0001u);
  EXPECT_EQ(word_mask(def(BankId::X, "x.15")), 0x8000u);
  EXPECT_EQ(word_mask(def(BankId::X, "x")), 0xFFFFu);
}

TEST_F(ValueCodec, WhatTakesMoreOrLessThanAWordIsReadOnly) {
  EXPECT_FALSE(writable(def(BankId::D1, "operating_hours")));
  EXPECT_FALSE(accepted(def(BankId::D1, "operating_hours")));
  EXPECT_EQ(refusal(raw_of(def(BankId::D1, "operating_hours"), 1)), "operating_hours is read only");
  EXPECT_TRUE(writable(def(BankId::W, "w_00")));
  EXPECT_TRUE(writable(def(BankId::X, "x")));
  EXPECT_TRUE(writable(def(BankId::X, "x.15")));
}

}  // namespace
}  // namespace unima::values
