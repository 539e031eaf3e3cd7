// What the C++ encoder writes, read by tests/support/sparkplug_decode.py — a decoder
// written from the Sparkplug specification and protobuf's encoding guide alone, which the
// integration tests will use on what the daemon publishes. Agreement here means the
// encoder's bytes are Sparkplug as a reader who never saw our code understands it.

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include <nlohmann/json.hpp>

#include "config/config.hpp"
#include "sparkplug/metric_value.hpp"
#include "sparkplug/payload_codec.hpp"
#include "sparkplug/value_metrics.hpp"
#include "tests/support/shell_command.hpp"
#include "tests/support/temp_files.hpp"
#include "values/store_snapshot.hpp"

namespace unima::sparkplug {
namespace {

class SparkplugIndependentDecoder : public ::testing::Test {
 protected:
  /// The decoder's JSON of `payload`'s bytes; a test failure when it refuses them.
  nlohmann::json decoded_by_python(const Payload& payload) {
    const auto bytes = encode_payload(payload);
    const auto file = dir.path() / "payload.bin";
    test_support::write_file(file, std::string(bytes.begin(), bytes.end()));
    const auto result = test_support::run("python3 " + script + " " + file.string() + " 2>&1");
    EXPECT_EQ(result.status, 0) << result.output;
    try {
      return nlohmann::json::parse(result.output);
    } catch (const nlohmann::json::exception&) {
      ADD_FAILURE() << "not JSON: " << result.output;
      return nullptr;
    }
  }

  test_support::TempDir dir;
  const std::string script = std::string(UNIMA_SOURCE_DIR) + "/tests/support/sparkplug_decode.py";
};

Metric named(std::string name, DataType type, MetricValue value) {
  Metric m;
  m.name = std::move(name);
  m.timestamp = 1700000000000;
  m.datatype = type;
  m.value = std::move(value);
  return m;
}

TEST_F(SparkplugIndependentDecoder, ReadsEveryDataTypeAsTheEncoderMeantIt) {
  Payload p;
  p.timestamp = 1700000000123;
  p.seq = 0;
  p.metrics.push_back(named("bdSeq", DataType::Int64, integer_value(DataType::Int64, 3)));
  p.metrics.push_back(named("Node Control/Rebirth", DataType::Boolean, false));
  p.metrics.push_back(named("i8", DataType::Int8, integer_value(DataType::Int8, -128)));
  p.metrics.push_back(named("i16", DataType::Int16, integer_value(DataType::Int16, -87)));
  p.metrics.push_back(named("i32", DataType::Int32, integer_value(DataType::Int32, -2147483647)));
  p.metrics.push_back(named("i64", DataType::Int64, integer_value(DataType::Int64, -5)));
  p.metrics.push_back(named("u8", DataType::UInt8, integer_value(DataType::UInt8, 200)));
  p.metrics.push_back(named("u16", DataType::UInt16, integer_value(DataType::UInt16, 65535)));
  p.metrics.push_back(named("u32", DataType::UInt32, integer_value(DataType::UInt32, 4294967295)));
  p.metrics.push_back(named("u64", DataType::UInt64, std::uint64_t{18446744073709551615u}));
  p.metrics.push_back(named("float", DataType::Float, -12.5f));
  p.metrics.push_back(named("double", DataType::Double, 429496729.5));
  p.metrics.push_back(named("string", DataType::String, std::string("K\xC3\xB6")));
  p.metrics.push_back(named("datetime", DataType::DateTime, std::uint64_t{1700000000000}));
  Metric null = named("null", DataType::Float, {});
  null.is_null = true;
  null.alias = 7;
  PropertyValue unit;
  unit.type = DataType::String;
  unit.value = std::string("\xC2\xB0" "C");
  PropertyValue quality;
  quality.type = DataType::Int32;
  quality.value = std::uint32_t{192};
  null.properties = PropertySet{{"engUnit", "Quality"}, {unit, quality}};
  p.metrics.push_back(null);

  const auto expected = nlohmann::json::parse(R"({
    "timestamp": 1700000000123, "seq": 0, "metrics": [
      {"name": "bdSeq", "timestamp": 1700000000000, "datatype": "Int64", "field": "long_value", "value": 3},
      {"name": "Node Control/Rebirth", "timestamp": 1700000000000, "datatype": "Boolean", "field": "boolean_value", "value": false},
      {"name": "i8", "timestamp": 1700000000000, "datatype": "Int8", "field": "int_value", "value": -128},
      {"name": "i16", "timestamp": 1700000000000, "datatype": "Int16", "field": "int_value", "value": -87},
      {"name": "i32", "timestamp": 1700000000000, "datatype": "Int32", "field": "int_value", "value": -2147483647},
      {"name": "i64", "timestamp": 1700000000000, "datatype": "Int64", "field": "long_value", "value": -5},
      {"name": "u8", "timestamp": 1700000000000, "datatype": "UInt8", "field": "int_value", "value": 200},
      {"name": "u16", "timestamp": 1700000000000, "datatype": "UInt16", "field": "int_value", "value": 65535},
      {"name": "u32", "timestamp": 1700000000000, "datatype": "UInt32", "field": "int_value", "value": 4294967295},
      {"name": "u64", "timestamp": 1700000000000, "datatype": "UInt64", "field": "long_value", "value": 18446744073709551615},
      {"name": "float", "timestamp": 1700000000000, "datatype": "Float", "field": "float_value", "value": -12.5},
      {"name": "double", "timestamp": 1700000000000, "datatype": "Double", "field": "double_value", "value": 429496729.5},
      {"name": "string", "timestamp": 1700000000000, "datatype": "String", "field": "string_value", "value": "Kö"},
      {"name": "datetime", "timestamp": 1700000000000, "datatype": "DateTime", "field": "long_value", "value": 1700000000000},
      {"name": "null", "alias": 7, "timestamp": 1700000000000, "datatype": "Float", "is_null": true,
       "properties": {"engUnit": {"type": "String", "value": "°C"}, "Quality": {"type": "Int32", "value": 192}}}
    ]})");
  EXPECT_EQ(decoded_by_python(p), expected);
}

TEST_F(SparkplugIndependentDecoder, ReadsADeviceBirthOfTheValueModel) {
  const auto config = config::load_text("devices:\n  D1: { type: unigen-chp, address: 5 }\n", "sparkplug.yaml");
  const values::ValueModel model(config);
  banks::RegisterStore store(config::bank_shapes(config));
  store.set_online(banks::BankId::D1, true);
  store.store_telegram(banks::BankId::D1, 0x00,
                       std::vector<std::uint16_t>{0x0805, 1500, 0x0010, 0x0002, static_cast<std::uint16_t>(-125), 0x7FFF});
  const auto& layout = *model.bank(banks::BankId::D1);
  const auto values = model.evaluate(banks::BankId::D1, values::snapshot_of(store));
  Payload birth;
  birth.timestamp = 1700000000000;
  birth.seq = 1;
  birth.metrics = metrics_of(layout, values, 1700000000000);

  const auto json = decoded_by_python(birth);
  ASSERT_EQ(json["metrics"].size(), birth.metrics.size());
  std::map<std::string, nlohmann::json> by_name;
  for (const auto& metric : json["metrics"]) by_name[metric["name"]] = metric;
  for (std::size_t i = 0; i < layout.values.size(); ++i) {
    const auto& def = layout.values[i];
    SCOPED_TRACE(def.name);
    ASSERT_TRUE(by_name.contains(def.name));
    const auto& metric = by_name[def.name];
    EXPECT_EQ(metric["datatype"], data_type_name(data_type_of(def)));
    EXPECT_EQ(metric["timestamp"], 1700000000000u);
    if (def.unit.empty())
      EXPECT_FALSE(metric.contains("properties"));
    else
      EXPECT_EQ(metric["properties"]["engUnit"], (nlohmann::json{{"type", "String"}, {"value", def.unit}}));
    const auto& reading = values[i].reading;
    if (std::holds_alternative<std::monostate>(reading)) {
      EXPECT_EQ(metric["is_null"], true);
      EXPECT_FALSE(metric.contains("value"));
    } else if (const auto* number = std::get_if<double>(&reading)) {
      EXPECT_NEAR(metric["value"].get<double>(), *number, 1e-6 * std::max(1.0, std::abs(*number)));
    } else if (const auto* flag = std::get_if<bool>(&reading)) {
      EXPECT_EQ(metric["value"], *flag);
    }
  }
  EXPECT_EQ(by_name["mains_active_power"]["value"], -12.5);
  EXPECT_EQ(by_name["operating_hours"]["value"], 2 * 65536 + 16);
  EXPECT_EQ(by_name["mains_reactive_power"]["is_null"], true) << "0x7FFF: not measured";
}

// X's bits are Boolean metrics beside the word: the decoder reads each in boolean_value.
TEST_F(SparkplugIndependentDecoder, ReadsXsBitsAsBooleanMetrics) {
  const auto config = config::load_text("", "sparkplug.yaml");
  const values::ValueModel model(config);
  banks::RegisterStore store(config::bank_shapes(config));
  store.write(banks::BankId::X, 0, 0x0021);
  Payload birth;
  birth.timestamp = 1700000000000;
  birth.seq = 1;
  birth.metrics = metrics_of(*model.bank(banks::BankId::X), model.evaluate(banks::BankId::X, values::snapshot_of(store)),
                             1700000000000);

  const auto json = decoded_by_python(birth);
  ASSERT_EQ(json["metrics"].size(), 17u);
  EXPECT_EQ(json["metrics"][0]["name"], "x");
  EXPECT_EQ(json["metrics"][0]["datatype"], "UInt16");
  EXPECT_EQ(json["metrics"][0]["value"], 0x0021);
  for (unsigned bit = 0; bit < 16; ++bit) {
    const auto& metric = json["metrics"][1 + bit];
    SCOPED_TRACE(bit);
    EXPECT_EQ(metric["name"], "x." + std::to_string(bit));
    EXPECT_EQ(metric["datatype"], "Boolean");
    EXPECT_EQ(metric["field"], "boolean_value");
    EXPECT_EQ(metric["value"], bit == 0 || bit == 5);
  }
}

TEST_F(SparkplugIndependentDecoder, RefusesWhatIsNoPayload) {
  const auto file = dir.path() / "cut.bin";
  test_support::write_file(file, std::string("\x12\x05\x0A", 3));
  const auto result = test_support::run("python3 " + script + " " + file.string() + " 2>&1");
  EXPECT_EQ(result.status, 1);
  EXPECT_NE(result.output.find("not a Sparkplug B payload"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace unima::sparkplug
