// mqtt::bank_documents (SPEC §12, §17): which banks are published and what their
// documents hold of the value model (when a bank is due: report_test).

#include <gtest/gtest.h>

#include <algorithm>

#include "config/config.hpp"
#include "mqtt/bank_documents.hpp"
#include "mqtt/command.hpp"
#include "values/store_snapshot.hpp"

namespace unima::mqtt {
namespace {

using namespace std::chrono_literals;

// A bank document holds the value model's values (SPEC §17) by their names, flat.
TEST(MqttDocuments, ValuesByTheirNamesFlatAndAByItsMappingSource) {
  const auto config = config::load_text(
      "devices: { D1: { type: unigen-chp, address: 5 }, D2: { type: uis, address: 6 } }\n"
      "mapping: { A: [ D1.oil_temperature ], B: [ X.0, D1+0x11.7 ] }\n",
      "mqtt.yaml");
  const values::ValueModel model(config);
  const auto published = published_banks(model);
  EXPECT_EQ(std::count(published.begin(), published.end(), banks::BankId::W), 0) << "W and X are not published";
  EXPECT_EQ(std::count(published.begin(), published.end(), banks::BankId::X), 0);
  EXPECT_EQ(std::count(published.begin(), published.end(), banks::BankId::D1), 1);

  banks::RegisterStore store(config::bank_shapes(config));
  store.set_mapping(config.mapping);
  store.set_online(banks::BankId::D1, true);
  store.set_online(banks::BankId::D2, true);
  const std::vector<std::uint16_t> d1 = {0x0042, 1500, 0x0010, 0x0002};
  store.store_telegram(banks::BankId::D1, 0, d1);
  const std::vector<std::uint16_t> oil = {853};
  store.store_telegram(banks::BankId::D1, 0x21, oil);
  const std::vector<std::uint16_t> control_inputs = {0};
  store.store_telegram(banks::BankId::D1, 0x11, control_inputs);
  const std::vector<std::uint16_t> uis = {0x0001, 41234};
  store.store_telegram(banks::BankId::D2, 0, uis);
  const std::vector<std::uint16_t> knock = {16 << 8 | 3};
  store.store_telegram(banks::BankId::D2, 0x08, knock);
  const auto snapshot = values::snapshot_of(store);
  const auto time = std::chrono::sys_days{std::chrono::year{2026} / 11 / 24} + 12h + 30min;
  const auto document = [&](banks::BankId bank) {
    return bank_document(*model.bank(bank), model.evaluate(bank, snapshot), snapshot[banks::index_of(bank)].online, time);
  };

  const auto chp = document(banks::BankId::D1);
  auto key = chp.begin();
  EXPECT_EQ(key.key(), "time");
  EXPECT_EQ((++key).key(), "online");
  EXPECT_EQ(chp["time"], "2026-11-24T12:30:00.000000Z");
  EXPECT_EQ(chp["engine_speed"], 1500);
  EXPECT_EQ(chp["operating_hours"], 2 * 65536 + 16) << "a 32-bit pair as one value";
  EXPECT_FALSE(chp.contains("operating_hours_low"));
  EXPECT_EQ(chp["status"], 0x42);
  EXPECT_EQ(chp["status.state"], 0x42) << "a bit word's fields beside the word, as dotted keys";
  EXPECT_EQ(chp["status.power_mode"], false);
  EXPECT_EQ(chp["oil_temperature"].dump(), "85.3");
  EXPECT_TRUE(chp["mains_active_power"].is_null()) << "not measured";

  const auto ignition = document(banks::BankId::D2);
  EXPECT_EQ(ignition["engine_speed"], 41234) << "unsigned where the table says so";
  EXPECT_EQ(ignition["knock_rank_1.cylinder"], 3) << "a byte pair as two values";
  EXPECT_DOUBLE_EQ(ignition["knock_rank_1.level"].get<double>(), 12.5);
  EXPECT_FALSE(ignition.contains("knock_rank_1"));
  EXPECT_FALSE(ignition.contains("reserve_06")) << "reserves are not published";

  const auto a = document(banks::BankId::A);
  EXPECT_EQ(a["D1.oil_temperature"].dump(), "85.3") << "the source as the config writes it, in its unit";
  EXPECT_FALSE(a.contains("a_01")) << "an unmapped entry is not published";
  const auto b = document(banks::BankId::B);
  EXPECT_EQ(b["D1+0x11.7"], false);
  EXPECT_FALSE(b.contains("X.0")) << "X was never written";

  store.set_online(banks::BankId::D1, false);
  const auto offline = values::snapshot_of(store);
  const auto gone = bank_document(*model.bank(banks::BankId::D1), model.evaluate(banks::BankId::D1, offline), false, time);
  EXPECT_EQ(gone["online"], false);
  EXPECT_TRUE(gone["status.power_mode"].is_null()) << "an off-line device's bits are null, not false";
  EXPECT_TRUE(gone["engine_speed"].is_null());
}

}  // namespace
}  // namespace unima::mqtt

namespace unima::mqtt {
namespace {

TEST(MqttCommands, WAndXWithTheirRangesAndANumberAsPayload) {
  const auto w = parse_command("W/3", "1234");
  ASSERT_TRUE(std::holds_alternative<Command>(w));
  EXPECT_EQ(std::get<Command>(w).bank, banks::BankId::W);
  EXPECT_EQ(std::get<Command>(w).offset, 3);
  EXPECT_EQ(std::get<Command>(w).value, 1234);
  EXPECT_EQ(std::get<Command>(parse_command("W/0x0F", "-1")).value, 0xFFFF);
  EXPECT_EQ(std::get<Command>(parse_command("W/15", " 0x8000\n")).value, 0x8000);
  const auto x = parse_command("X/10", "1");
  ASSERT_TRUE(std::holds_alternative<Command>(x));
  EXPECT_EQ(std::get<Command>(x).bank, banks::BankId::X);
  EXPECT_EQ(std::get<Command>(x).offset, 10);

  const auto error = [](std::string_view topic, std::string_view payload) {
    const auto parsed = parse_command(topic, payload);
    return std::holds_alternative<std::string>(parsed) ? std::get<std::string>(parsed) : std::string("accepted");
  };
  EXPECT_EQ(error("W/16", "1"), "W has the offsets 0..15, not '16'");
  EXPECT_EQ(error("W/-1", "1"), "W has the offsets 0..15, not '-1'");
  EXPECT_EQ(error("X/16", "1"), "X has the bits 0..15, not '16'");
  EXPECT_EQ(error("X/3", "2"), "the payload must be 0 or 1, not '2'");
  EXPECT_EQ(error("W/1", "12.5"), "the payload must be a whole number -32768..65535, not '12.5'");
  EXPECT_EQ(error("W/1", "65536"), "the payload must be a whole number -32768..65535, not '65536'");
  EXPECT_EQ(error("W/1", ""), "the payload must be a whole number -32768..65535, not ''");
  EXPECT_EQ(error("C/1", "1"), "commands are set/W/<offset> and set/X/<bit>");
  EXPECT_EQ(error("W", "1"), "commands are set/W/<offset> and set/X/<bit>");
  EXPECT_EQ(command_result("p/set/W/1", ""), R"({"topic":"p/set/W/1","ok":true,"error":null})");
  EXPECT_EQ(command_result("p/set/W/1", "no \"W\""), R"({"topic":"p/set/W/1","ok":false,"error":"no \"W\""})");
}

}  // namespace
}  // namespace unima::mqtt
