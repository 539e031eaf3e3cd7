// mqtt::bank_documents (SPEC §12): which banks are published and how a value reads in
// engineering units, and when a bank is due.

#include <gtest/gtest.h>

#include "mqtt/bank_documents.hpp"
#include "mqtt/command.hpp"

namespace unima::mqtt {
namespace {

using namespace std::chrono_literals;

config::MapRow row(std::string bank, std::string id, std::string kind, double scale, std::string source = "") {
  config::MapRow r;
  r.bank = std::move(bank);
  r.id = std::move(id);
  r.kind = std::move(kind);
  r.scale = scale;
  r.source = std::move(source);
  return r;
}

TEST(MqttDocuments, BanksByTheirTableIdentifiersAndAByItsMappingSource) {
  std::vector<config::MapRow> rows = {
      row("A", "a_00", "analog", 0.1, "D1.oil_temperature (raw)"), row("D1", "engine_speed", "analog", 1),
      row("D1", "oil_temperature", "analog", 0.1), row("D1", "status_word", "bits", 1), row("W", "w_00", "analog", 1),
      row("read", "r_00", "analog", 1), row("B", "b", "bits", 1, "0=X.0 3=D1+0x15.3")};
  banks::Mapping mapping;
  mapping.analog[0] = banks::SourceRef{};
  mapping.analog[0]->text = "D1.oil_temperature";
  mapping.bits[0] = banks::SourceRef{};
  mapping.bits[0]->text = "X.0";
  mapping.bits[3] = banks::SourceRef{};
  mapping.bits[3]->text = "D1+0x15.3";
  const auto layouts = bank_layouts(rows, mapping);
  ASSERT_EQ(layouts.size(), 3u) << "W and blocks are not published";
  EXPECT_EQ(layouts[0].bank, "A");
  EXPECT_EQ(layouts[0].registers[0].key, "D1.oil_temperature") << "the source as the config writes it";
  EXPECT_EQ(layouts[1].bank, "D1");
  ASSERT_EQ(layouts[1].registers.size(), 3u);
  EXPECT_EQ(layouts[2].bank, "B");
  ASSERT_EQ(layouts[2].registers.size(), 2u) << "one entry per mapped bit";

  const std::vector<std::optional<std::uint16_t>> values = {853, 1500, 0x7FFF, 0x8001, 7, std::nullopt, 0b1000};
  const auto time = std::chrono::sys_days{std::chrono::year{2026} / 11 / 24} + 12h + 30min;
  const auto d1 = bank_document(layouts[1], values, true, time);
  EXPECT_EQ(d1.dump(), R"({"time":"2026-11-24T12:30:00.000000Z","online":true,"engine_speed":1500,"oil_temperature":null,"status_word":32769})");
  const auto a = bank_document(layouts[0], values, true, time);
  EXPECT_DOUBLE_EQ(a["D1.oil_temperature"].get<double>(), 85.3);
  EXPECT_EQ(a["D1.oil_temperature"].dump(), "85.3");
  const auto b = bank_document(layouts[2], values, true, time);
  EXPECT_EQ(b["X.0"], 0);
  EXPECT_EQ(b["D1+0x15.3"], 1);
}

TEST(MqttDocuments, SignedValuesAndScalesInEngineeringUnits) {
  const BankRegister tenths{"t", "analog", 0.1, 0, std::nullopt};
  EXPECT_EQ(engineering_value(tenths, 0xFFF6).dump(), "-1.0");
  EXPECT_EQ(engineering_value(tenths, 0x7FFF), nullptr);
  EXPECT_EQ(engineering_value(tenths, std::nullopt), nullptr);
  const BankRegister bits{"b", "bits", 1, 0, std::nullopt};
  EXPECT_EQ(engineering_value(bits, 0x7FFF), 0x7FFF) << "only an analog value can be not measured";
  const BankRegister hundredths{"h", "analog", 0.01, 0, std::nullopt};
  EXPECT_EQ(engineering_value(hundredths, 12345).dump(), "123.45");
}

TEST(MqttSchedule, ChangedBanksAtMostEvery100msAndAllEveryPeriodAndAfterAReconnect) {
  PublishSchedule schedule(3, 10s, true);
  const auto t0 = PublishSchedule::Clock::now();
  EXPECT_EQ(schedule.due({"a", "b", "c"}, t0), (std::vector<std::size_t>{0, 1, 2})) << "everything first";
  EXPECT_TRUE(schedule.due({"a", "b", "c"}, t0 + 50ms).empty());
  EXPECT_TRUE(schedule.due({"a", "B", "c"}, t0 + 50ms).empty()) << "changed, but published 50 ms ago";
  EXPECT_EQ(schedule.due({"a", "B", "c"}, t0 + 100ms), (std::vector<std::size_t>{1}));
  EXPECT_TRUE(schedule.due({"a", "B", "c"}, t0 + 5s).empty());
  EXPECT_EQ(schedule.due({"a", "B", "c"}, t0 + 10s), (std::vector<std::size_t>{0, 1, 2})) << "the period";
  schedule.publish_all();
  EXPECT_EQ(schedule.due({"a", "B", "c"}, t0 + 10s + 1ms).size(), 3u) << "a reconnect";

  PublishSchedule periodic_only(2, 10s, false);
  EXPECT_EQ(periodic_only.due({"a", "b"}, t0).size(), 2u);
  EXPECT_TRUE(periodic_only.due({"x", "y"}, t0 + 1s).empty());
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
