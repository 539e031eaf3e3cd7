// values/ (SPEC §17): what the page, /api/registers and MQTT show of a register — one
// model, from the device tables and the mapping, fed here from a real register store.

#include <gtest/gtest.h>

#include <algorithm>

#include "config/config.hpp"
#include "values/store_snapshot.hpp"
#include "values/value_json.hpp"
#include "values/value_model.hpp"

namespace unima::values {
namespace {

using banks::BankId;

const std::string config_yaml =
    "devices:\n"
    "  D1: { type: unigen-chp, address: 5 }\n"
    "  D2: { type: uis, address: 6 }\n"
    "  D3: { type: nsu2, address: 7 }\n"
    "mapping:\n"
    "  A: [ D1.engine_speed, D1.mains_active_power ]\n"
    "  B: [ D1+0x11.7, X.2 ]\n"
    "  user_inputs: [ D1.remote_start ]\n";

class ValuesTest : public ::testing::Test {
 protected:
  ValuesTest() : config(config::load_text(config_yaml, "values.yaml")), model(config), store(config::bank_shapes(config)) {
    store.set_mapping(config.mapping);
    for (const auto bank : {BankId::D1, BankId::D2, BankId::D3}) store.set_online(bank, true);
  }

  void feed(BankId bank, std::uint16_t offset, std::vector<std::uint16_t> registers) {
    store.store_telegram(bank, offset, registers);
  }

  /// The value named `name` of `bank` as the model reads the store now, as JSON.
  nlohmann::json value(BankId bank, std::string_view name) const {
    const auto* layout = model.bank(bank);
    if (!layout) return "no bank";
    const auto found =
        std::find_if(layout->values.begin(), layout->values.end(), [&](const ValueDef& d) { return d.name == name; });
    if (found == layout->values.end()) return "no value";
    const auto index = static_cast<std::size_t>(found - layout->values.begin());
    return value_json(*found, model.evaluate(bank, snapshot_of(store))[index]);
  }

  std::vector<std::string> names(BankId bank) const {
    std::vector<std::string> all;
    for (const auto& d : model.bank(bank)->values) all.push_back(d.name);
    return all;
  }

  config::Config config;
  ValueModel model;
  banks::RegisterStore store;
};

bool has(const std::vector<std::string>& names, std::string_view name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

TEST_F(ValuesTest, A32BitPairIsOneValueAndNullWhenEitherHalfIsNotMeasured) {
  feed(BankId::D1, 0x02, {0x0010, 0x0002});
  const auto hours = value(BankId::D1, "operating_hours");
  EXPECT_EQ(hours["value"], 2 * 65536 + 16) << hours;
  EXPECT_EQ(hours["unit"], "s");
  EXPECT_EQ(hours["state"], "ok");
  const auto& defs = model.bank(BankId::D1)->values;
  const auto def = std::find_if(defs.begin(), defs.end(), [](const ValueDef& d) { return d.name == "operating_hours"; });
  ASSERT_NE(def, defs.end());
  EXPECT_EQ(def->label, "Motohodiny") << "the quantity, not the low word the seed's label names";
  const auto d1 = names(BankId::D1);
  EXPECT_FALSE(has(d1, "operating_hours_low")) << "the halves are not values of their own";
  EXPECT_FALSE(has(d1, "operating_hours_high"));

  feed(BankId::D1, 0x03, {0x7FFF});
  EXPECT_EQ(value(BankId::D1, "operating_hours")["value"], nullptr);
  EXPECT_EQ(value(BankId::D1, "operating_hours")["state"], "not measured");
  feed(BankId::D1, 0x02, {0x7FFF, 0x0002});
  EXPECT_EQ(value(BankId::D1, "operating_hours")["state"], "not measured");
}

TEST_F(ValuesTest, ABytePairIsTwoValuesEachInItsUnitAndAByteOf255IsNotMeasured) {
  feed(BankId::D2, 0x08, {16 << 8 | 3});  // level 16 × 0.78125 %, cylinder 3
  const auto cylinder = value(BankId::D2, "knock_rank_1.cylinder");
  const auto level = value(BankId::D2, "knock_rank_1.level");
  EXPECT_EQ(cylinder["value"], 3) << cylinder;
  EXPECT_EQ(cylinder["unit"], "");
  EXPECT_DOUBLE_EQ(level["value"].get<double>(), 12.5) << level;
  EXPECT_EQ(level["unit"], "%");
  EXPECT_FALSE(has(names(BankId::D2), "knock_rank_1")) << "the pair itself is not a value";

  feed(BankId::D2, 0x08, {0xFF << 8 | 3});
  EXPECT_EQ(value(BankId::D2, "knock_rank_1.level")["value"], nullptr);
  EXPECT_EQ(value(BankId::D2, "knock_rank_1.level")["state"], "not measured");
  EXPECT_EQ(value(BankId::D2, "knock_rank_1.cylinder")["value"], 3) << "its sibling is measured";
}

TEST_F(ValuesTest, ABitWordIsTheWordAndItsNamedBitsAsBooleansAndBitRangesAsNumbers) {
  feed(BankId::D1, 0x11, {1u << 7});
  EXPECT_EQ(value(BankId::D1, "control_inputs")["value"], 128);
  EXPECT_EQ(value(BankId::D1, "control_inputs.remote_start")["value"], true);
  EXPECT_EQ(value(BankId::D1, "control_inputs.user_start_block")["value"], false);

  feed(BankId::D1, 0x00, {1u << 11 | 6u << 8 | 0x42});
  EXPECT_EQ(value(BankId::D1, "status.state")["value"], 0x42);
  EXPECT_EQ(value(BankId::D1, "status.unit_mode")["value"], 6);
  EXPECT_EQ(value(BankId::D1, "status.power_mode")["value"], true);
}

// A bit word is "bits" whether the seed names its bits (control_inputs) or not
// (status_word): the page shows it in hex; its fields are booleans and numbers.
TEST_F(ValuesTest, EveryBitWordIsOfTypeBitsAndItsFieldsOfTheirOwnType) {
  const auto type = [&](BankId bank, std::string_view name) {
    const auto& values = model.bank(bank)->values;
    const auto found = std::find_if(values.begin(), values.end(), [&](const ValueDef& d) { return d.name == name; });
    return found == values.end() ? std::string_view("no value") : type_name(*found);
  };
  EXPECT_EQ(type(BankId::D1, "control_inputs"), "bits");
  EXPECT_EQ(type(BankId::D1, "status_word"), "bits");
  EXPECT_EQ(type(BankId::D1, "control_inputs.remote_start"), "boolean");
  EXPECT_EQ(type(BankId::D1, "status.state"), "number");
  EXPECT_EQ(type(BankId::D1, "engine_speed"), "number");
}

TEST_F(ValuesTest, SignedWhereTheTableSaysSoAndUnsignedOtherwise) {
  feed(BankId::D2, 0x01, {41234});
  EXPECT_EQ(value(BankId::D2, "engine_speed")["value"], 41234) << "engine_speed is unsigned";
  feed(BankId::D1, 0x04, {0xFFF6});
  EXPECT_EQ(value(BankId::D1, "mains_active_power")["value"].dump(), "-1.0");
  EXPECT_EQ(value(BankId::D1, "mains_active_power")["unit"], "kW");
  feed(BankId::D1, 0x04, {0x7FFF});
  EXPECT_EQ(value(BankId::D1, "mains_active_power")["state"], "not measured");
}

TEST_F(ValuesTest, AnAsciiPairIsTwoCharactersInTheTablesOrder) {
  feed(BankId::D3, 0x28, {'B' << 8 | 'A'});
  EXPECT_EQ(value(BankId::D3, "display_line1_chars_01_02")["value"], "AB");
}

TEST_F(ValuesTest, ReservesAreNotValues) {
  EXPECT_FALSE(has(names(BankId::D2), "reserve_06"));
  EXPECT_FALSE(has(names(BankId::D3), "reserve_01"));
  EXPECT_FALSE(has(names(BankId::C), "reserve_11"));
  EXPECT_TRUE(has(names(BankId::D2), "ignition_advance"));
}

TEST_F(ValuesTest, AnOfflineDeviceHasEveryValueNullEvenItsBits) {
  feed(BankId::D1, 0x00, {0x0042, 1500, 0x0010, 0x0002});
  feed(BankId::D1, 0x11, {0xFFFF});
  store.set_online(BankId::D1, false);
  const auto values = model.evaluate(BankId::D1, snapshot_of(store));
  ASSERT_FALSE(values.empty());
  for (const auto& v : values) {
    EXPECT_TRUE(std::holds_alternative<std::monostate>(v.reading));
    EXPECT_EQ(v.state, State::offline);
  }
  EXPECT_EQ(value(BankId::D1, "control_inputs.remote_start")["value"], nullptr) << "not false: null";
  EXPECT_EQ(value(BankId::D1, "control_inputs.remote_start")["state"], "off-line");
  EXPECT_EQ(value(BankId::A, "D1.engine_speed")["state"], "off-line") << "an entry of A says why its source has no value";
}

TEST_F(ValuesTest, BankAShowsEachMappedEntryInItsSourcesUnitKeyedByItsSource) {
  feed(BankId::D1, 0x01, {1500});  // A holds 15000 tenths of min-1
  feed(BankId::D1, 0x04, {0xFFF6});
  const auto speed = value(BankId::A, "D1.engine_speed");
  EXPECT_DOUBLE_EQ(speed["value"].get<double>(), 1500.0) << speed;
  EXPECT_EQ(speed["unit"], "min-1");
  EXPECT_DOUBLE_EQ(value(BankId::A, "D1.mains_active_power")["value"].get<double>(), -1.0);
  const auto unmapped = value(BankId::A, "a_02");
  EXPECT_EQ(unmapped["value"], nullptr);
  EXPECT_EQ(unmapped["state"], "not mapped");
  EXPECT_FALSE(published(model.evaluate(BankId::A, snapshot_of(store))[2]));
  EXPECT_TRUE(published(model.evaluate(BankId::A, snapshot_of(store))[0]));
}

TEST_F(ValuesTest, BankBShowsMappedBitsAsBooleansKeyedByTheirSources) {
  feed(BankId::D1, 0x11, {1u << 7});
  EXPECT_EQ(value(BankId::B, "D1+0x11.7")["value"], true);
  EXPECT_EQ(value(BankId::B, "X.2")["state"], "not set") << "X was never written";
  store.write(BankId::X, 0, 1u << 2);
  EXPECT_EQ(value(BankId::B, "X.2")["value"], true);
}

TEST_F(ValuesTest, TheUserBitsOfCAreMappedBitsLikeB) {
  EXPECT_EQ(value(BankId::C, "user_binary_inputs.user_binary_input_1")["state"], "not measured")
      << "D1 on line, its control_inputs never carried";
  EXPECT_EQ(value(BankId::C, "user_binary_inputs.user_binary_input_2")["state"], "not mapped");
  feed(BankId::D1, 0x11, {1u << 7});
  EXPECT_EQ(value(BankId::C, "user_binary_inputs.user_binary_input_1")["value"], true);
  store.set_online(BankId::D1, false);
  EXPECT_EQ(value(BankId::C, "user_binary_inputs.user_binary_input_1")["state"], "off-line");
  EXPECT_EQ(value(BankId::C, "user_binary_inputs")["value"], 0) << "the word reads as Modbus reads it";
}

TEST_F(ValuesTest, WNeverWrittenIsNotSetAndWrittenIsItsValue) {
  const auto unset = value(BankId::W, "w_00");
  EXPECT_EQ(unset["value"], nullptr);
  EXPECT_EQ(unset["state"], "not set");
  EXPECT_EQ(unset["set"], false);
  EXPECT_FALSE(published(model.evaluate(BankId::W, snapshot_of(store))[0]));
  store.write(BankId::W, 0, 125);
  const auto set = value(BankId::W, "w_00");
  EXPECT_DOUBLE_EQ(set["value"].get<double>(), 12.5);
  EXPECT_EQ(set["state"], "ok");
  EXPECT_FALSE(set.contains("set"));
}

TEST_F(ValuesTest, ARegisterNoTelegramCarriedYetIsNotMeasuredEvenABitWord) {
  EXPECT_EQ(value(BankId::D1, "control_inputs")["state"], "not measured");
  EXPECT_EQ(value(BankId::D1, "control_inputs.remote_start")["value"], nullptr);
}

TEST_F(ValuesTest, ADeviceBankWithoutADeviceHasNoValues) { EXPECT_EQ(model.bank(BankId::D4), nullptr); }

}  // namespace
}  // namespace unima::values
