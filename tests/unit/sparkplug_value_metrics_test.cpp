// sparkplug/value_metrics (SPEC §16, §17): the value model's values as the metrics of a
// DBIRTH and a DDATA — datatype per kind of value, engUnit, is_null — fed from a real
// register store through values::ValueModel, as the session will feed them.

#include <gtest/gtest.h>

#include <algorithm>

#include "config/config.hpp"
#include "sparkplug/metric_value.hpp"
#include "sparkplug/value_metrics.hpp"
#include "values/store_snapshot.hpp"

namespace unima::sparkplug {
namespace {

using banks::BankId;

const std::string config_yaml =
    "devices:\n"
    "  D1: { type: unigen-chp, address: 5 }\n"
    "  D2: { type: uis, address: 6 }\n"
    "  D3: { type: nsu2, address: 7 }\n"
    "  D4: { type: uvr, address: 8 }\n"
    "mapping:\n"
    "  A: [ D1.engine_speed, D1.mains_active_power ]\n"
    "  B: [ D1+0x11.7 ]\n";

constexpr std::uint64_t now_ms = 1700000000123;

class SparkplugValueMetrics : public ::testing::Test {
 protected:
  SparkplugValueMetrics()
      : config(config::load_text(config_yaml, "sparkplug.yaml")), model(config), store(config::bank_shapes(config)) {
    store.set_mapping(config.mapping);
    for (const auto bank : {BankId::D1, BankId::D2, BankId::D3, BankId::D4}) store.set_online(bank, true);
  }

  std::vector<values::Value> values_of(BankId bank) const { return model.evaluate(bank, values::snapshot_of(store)); }

  std::vector<Metric> birth(BankId bank) const { return metrics_of(*model.bank(bank), values_of(bank), now_ms); }

  static Metric find(const std::vector<Metric>& metrics, std::string_view name) {
    const auto found = std::find_if(metrics.begin(), metrics.end(), [&](const Metric& m) { return m.name == name; });
    if (found == metrics.end()) throw std::runtime_error("no metric " + std::string(name));
    return *found;
  }

  static std::string unit_of(const Metric& m) {
    if (!m.properties) return "(none)";
    const auto* unit = m.properties->find("engUnit");
    if (!unit || unit->type != DataType::String) return "(not a String engUnit)";
    return std::get<std::string>(unit->value);
  }

  config::Config config;
  values::ValueModel model;
  banks::RegisterStore store;
};

TEST_F(SparkplugValueMetrics, EachKindOfValueHasItsDatatypeAndReading) {
  store.store_telegram(BankId::D1, 0x00, std::vector<std::uint16_t>{0x0805, 1500, 0x0010, 0x0002, static_cast<std::uint16_t>(-125)});
  const auto d1 = birth(BankId::D1);

  const auto& speed = find(d1, "engine_speed");
  EXPECT_EQ(speed.datatype, DataType::UInt16);
  EXPECT_EQ(number_of(speed.value, DataType::UInt16), 1500.0);
  EXPECT_EQ(unit_of(speed), "min-1");
  EXPECT_EQ(speed.timestamp, now_ms);
  EXPECT_FALSE(speed.is_null.has_value());

  const auto& hours = find(d1, "operating_hours");
  EXPECT_EQ(hours.datatype, DataType::UInt64) << "read alike by the specification and Tahu's codecs";
  EXPECT_EQ(hours.value, MetricValue(std::uint64_t{2 * 65536 + 16}));
  EXPECT_EQ(unit_of(hours), "s");

  const auto& power = find(d1, "mains_active_power");
  EXPECT_EQ(power.datatype, DataType::Float);
  EXPECT_EQ(power.value, MetricValue(-12.5f));
  EXPECT_EQ(unit_of(power), "kW");

  EXPECT_EQ(find(d1, "status").datatype, DataType::UInt16) << "a bit word as a whole";
  EXPECT_EQ(find(d1, "status").value, MetricValue(std::uint32_t{0x0805}));
  EXPECT_EQ(find(d1, "status.state").datatype, DataType::UInt16) << "a field of several bits";
  EXPECT_EQ(find(d1, "status.state").value, MetricValue(std::uint32_t{5}));
  EXPECT_EQ(find(d1, "status.power_mode").datatype, DataType::Boolean);
  EXPECT_EQ(find(d1, "status.power_mode").value, MetricValue(true));
  EXPECT_EQ(unit_of(find(d1, "status")), "(none)") << "no unit, no property";

  store.store_telegram(BankId::D2, 0x08, std::vector<std::uint16_t>{0x4003});
  const auto d2 = birth(BankId::D2);
  EXPECT_EQ(find(d2, "knock_rank_1.cylinder").datatype, DataType::UInt8);
  EXPECT_EQ(find(d2, "knock_rank_1.cylinder").value, MetricValue(std::uint32_t{3}));
  EXPECT_EQ(find(d2, "knock_rank_1.level").datatype, DataType::Float);
  EXPECT_EQ(find(d2, "knock_rank_1.level").value, MetricValue(50.0f));  // 0x40 × 0.78125
  EXPECT_EQ(unit_of(find(d2, "knock_rank_1.level")), "%");

  store.store_telegram(BankId::D3, 0x28, std::vector<std::uint16_t>{'O' << 8 | 'K'});
  const auto text = find(birth(BankId::D3), "display_line1_chars_01_02");
  EXPECT_EQ(text.datatype, DataType::String);
  EXPECT_EQ(text.value, MetricValue(std::string("KO"))) << "the low byte first, as the table says";

  store.store_telegram(BankId::D4, 0x07, std::vector<std::uint16_t>{static_cast<std::uint16_t>(-3)});
  const auto setpoint = find(birth(BankId::D4), "power_factor_setpoint");
  EXPECT_EQ(setpoint.datatype, DataType::Int16);
  EXPECT_EQ(setpoint.value, MetricValue(std::uint32_t{0xFFFFFFFD})) << "two's complement, sign-extended";
  EXPECT_EQ(number_of(setpoint.value, DataType::Int16), -3.0);
}

TEST_F(SparkplugValueMetrics, NotMeasuredAndOfflineAreNullWithTheirDatatypeAndUnit) {
  store.store_telegram(BankId::D1, 0x01, std::vector<std::uint16_t>{0x7FFF});
  const auto speed = find(birth(BankId::D1), "engine_speed");
  EXPECT_EQ(speed.is_null, true);
  EXPECT_EQ(speed.datatype, DataType::UInt16);
  EXPECT_TRUE(std::holds_alternative<std::monostate>(speed.value));
  EXPECT_EQ(unit_of(speed), "min-1");

  store.store_telegram(BankId::D1, 0x00, std::vector<std::uint16_t>{0x0805});
  store.set_online(BankId::D1, false);
  for (const auto& metric : birth(BankId::D1)) {
    EXPECT_EQ(metric.is_null, true) << *metric.name << ": every value of an off-line device, bits too";
    EXPECT_TRUE(metric.datatype.has_value());
  }
}

TEST_F(SparkplugValueMetrics, BankAAndBCarryTheirMappedEntriesOnly) {
  store.store_telegram(BankId::D1, 0x01, std::vector<std::uint16_t>{1500});
  const auto a = birth(BankId::A);
  ASSERT_EQ(a.size(), 2u) << "the two mapped entries; the fourteen unmapped have no metric";
  EXPECT_EQ(a[0].name, "D1.engine_speed");
  EXPECT_EQ(a[0].datatype, DataType::Float) << "A holds an analog source in tenths of its unit";
  EXPECT_EQ(a[0].value, MetricValue(1500.0f));
  EXPECT_EQ(unit_of(a[0]), "min-1");
  EXPECT_EQ(a[1].name, "D1.mains_active_power");
  EXPECT_EQ(a[1].datatype, DataType::Float);
  EXPECT_EQ(a[1].is_null, true) << "its source was never measured";

  const auto b = birth(BankId::B);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(b[0].name, "D1+0x11.7");
  EXPECT_EQ(b[0].datatype, DataType::Boolean);
}

TEST_F(SparkplugValueMetrics, WAndXNeverWrittenAreInTheBirthAsNull) {
  const auto w = birth(BankId::W);
  ASSERT_EQ(w.size(), 16u) << "a later write must have a metric to land in";
  EXPECT_EQ(w[3].name, "w_03");
  EXPECT_EQ(w[3].datatype, DataType::Float);
  EXPECT_EQ(w[3].is_null, true);
  const auto x = birth(BankId::X);
  ASSERT_EQ(x.size(), 17u) << "the word and each of its sixteen bits";
  EXPECT_EQ(x[0].name, "x");
  EXPECT_EQ(x[0].datatype, DataType::UInt16);
  EXPECT_EQ(x[0].is_null, true);
  for (unsigned bit = 0; bit < 16; ++bit) {
    EXPECT_EQ(x[1 + bit].name, "x." + std::to_string(bit));
    EXPECT_EQ(x[1 + bit].datatype, DataType::Boolean) << "SPEC §16: Boolean for bits";
    EXPECT_EQ(x[1 + bit].is_null, true);
    EXPECT_FALSE(x[1 + bit].properties.has_value()) << "a bit has no unit";
  }

  store.write(BankId::W, 3, static_cast<std::uint16_t>(-15));
  EXPECT_EQ(birth(BankId::W)[3].value, MetricValue(-1.5f));
  store.write(BankId::X, 0, 0x8004);
  const auto written = birth(BankId::X);
  EXPECT_EQ(written[0].value, MetricValue(std::uint32_t{0x8004}));
  EXPECT_EQ(written[1 + 2].value, MetricValue(true));
  EXPECT_EQ(written[1 + 15].value, MetricValue(true));
  EXPECT_EQ(written[1 + 3].value, MetricValue(false));
  EXPECT_FALSE(written[1 + 3].is_null.value_or(false)) << "false, not null";
}

TEST_F(SparkplugValueMetrics, ADataMessageOfXCarriesTheWordAndTheBitsThatChanged) {
  const auto& layout = *model.bank(BankId::X);
  store.write(BankId::X, 0, 0x0001);
  const auto sent = values_of(BankId::X);
  store.write(BankId::X, 0, 0x0101);
  const auto changed = changed_metrics_of(layout, sent, values_of(BankId::X), now_ms);
  ASSERT_EQ(changed.size(), 2u);
  EXPECT_EQ(changed[0].name, "x");
  EXPECT_EQ(changed[0].value, MetricValue(std::uint32_t{0x0101}));
  EXPECT_EQ(changed[1].name, "x.8");
  EXPECT_EQ(changed[1].datatype, DataType::Boolean);
  EXPECT_EQ(changed[1].value, MetricValue(true));
}

TEST_F(SparkplugValueMetrics, ADataMessageCarriesWhatChangedAndNothingElse) {
  store.store_telegram(BankId::D1, 0x01, std::vector<std::uint16_t>{1500});
  const auto& layout = *model.bank(BankId::D1);
  const auto sent = values_of(BankId::D1);
  EXPECT_TRUE(changed_metrics_of(layout, sent, sent, now_ms).empty());

  store.store_telegram(BankId::D1, 0x01, std::vector<std::uint16_t>{1501});
  auto changed = changed_metrics_of(layout, sent, values_of(BankId::D1), now_ms + 5);
  ASSERT_EQ(changed.size(), 1u);
  EXPECT_EQ(changed[0].name, "engine_speed");
  EXPECT_EQ(changed[0].datatype, DataType::UInt16);
  EXPECT_EQ(changed[0].value, MetricValue(std::uint32_t{1501}));
  EXPECT_EQ(changed[0].timestamp, now_ms + 5);
  EXPECT_FALSE(changed[0].properties.has_value()) << "the unit is the birth's";

  store.store_telegram(BankId::D1, 0x01, std::vector<std::uint16_t>{0x7FFF});
  const auto not_measured = values_of(BankId::D1);
  changed = changed_metrics_of(layout, sent, not_measured, now_ms);
  ASSERT_EQ(changed.size(), 1u);
  EXPECT_EQ(changed[0].is_null, true);
  EXPECT_EQ(changed[0].datatype, DataType::UInt16);

  store.set_online(BankId::D1, false);
  const auto offline = values_of(BankId::D1);
  for (const auto& metric : changed_metrics_of(layout, not_measured, offline, now_ms))
    EXPECT_NE(metric.name, "engine_speed") << "null before and after: no change on Sparkplug";
}

}  // namespace
}  // namespace unima::sparkplug
