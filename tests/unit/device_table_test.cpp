// The device table parser (SPEC §2): a table's head read alone, a whole table, the errors
// it names by file, line and column, and the value a register of each kind reads off line.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "banks/bank_id.hpp"
#include "banks/device_table.hpp"
#include "tests/support/error_message.hpp"

namespace unima::banks {
namespace {

TEST(TableHead, IsReadFromTheLinesBeforeTheRegisters) {
  const auto head = parse_device_table_head(
      "# a table\nid: pump\naliases: [p1, p2]\ndevices: \"Pump\"\nregisters:\n  - { offset: oops\n", "pump.yaml");
  EXPECT_EQ(head.id, "pump");
  EXPECT_EQ(head.aliases, (std::vector<std::string>{"p1", "p2"}));
}

TEST(TableHead, NamesFileLineAndColumnOfAnError) {
  try {
    parse_device_table_head("devices: \"Pump\"\naliases: p1\nregisters: []\n", "pump.yaml");
    FAIL() << "no error";
  } catch (const TableError& e) {
    EXPECT_STREQ(e.what(), "pump.yaml:1:1: missing key 'id'");
  }
  try {
    parse_device_table_head("id: pump\naliases: p1\n", "pump.yaml");
    FAIL() << "no error";
  } catch (const TableError& e) {
    EXPECT_STREQ(e.what(), "pump.yaml:2:10: aliases must be a list");
  }
}

TEST(ParseDeviceTable, MinimalTable) {
  const auto t = parse_device_table(
      "id: demo\n"
      "aliases: [demo-2]\n"
      "registers:\n"
      "  - { offset: 0x00, id: status, kind: bits, fields: [ { bits: \"0-7\", id: state }, { bits: \"9\", id: run } ] }\n"
      "  - { offset: 0x01, id: power, kind: analog, signed: true, unit: kW, scale: 0.1 }\n"
      "  - { offset: 0x02, id: hours_low, kind: u32_low, pair: hours }\n"
      "  - { offset: 0x03, id: hours_high, kind: u32_high, pair: hours }\n",
      "demo.yaml");
  EXPECT_EQ(t.id, "demo");
  ASSERT_EQ(t.aliases.size(), 1u);
  EXPECT_EQ(t.aliases[0], "demo-2");
  ASSERT_EQ(t.length(), 4);
  EXPECT_EQ(t.registers[1].unit, "kW");
  EXPECT_DOUBLE_EQ(t.registers[1].scale, 0.1);
  ASSERT_EQ(t.registers[0].fields.size(), 2u);
  EXPECT_EQ(t.registers[0].fields[0].first_bit, 0);
  EXPECT_EQ(t.registers[0].fields[0].last_bit, 7);
  const auto run = t.find_bit("run");
  ASSERT_TRUE(run.has_value());
  EXPECT_EQ(run->offset, 0);
  EXPECT_EQ(run->bit, 9);
  EXPECT_FALSE(t.find_bit("state").has_value());  // a range, not a single bit
}

std::string table_error(const std::string& yaml) {
  return test_support::error_message<TableError>([&] { (void)parse_device_table(yaml, "tables/t.yaml"); });
}

bool starts_with(const std::string& text, const std::string& prefix) { return text.rfind(prefix, 0) == 0; }

TEST(ParseDeviceTable, UnknownKey) {
  const auto message = table_error(
      "id: t\n"
      "registers:\n"
      "  - offset: 0x00\n"
      "    id: a\n"
      "    kind: analog\n"
      "    signed: false\n"
      "    colour: red\n");
  EXPECT_TRUE(starts_with(message, "tables/t.yaml:7:5: ")) << message;
  EXPECT_NE(message.find("colour"), std::string::npos) << message;
}

TEST(ParseDeviceTable, DuplicateId) {
  const auto message = table_error(
      "id: t\n"
      "registers:\n"
      "  - offset: 0x00\n"
      "    id: a\n"
      "    kind: analog\n"
      "    signed: false\n"
      "  - offset: 0x01\n"
      "    id: a\n"
      "    kind: analog\n"
      "    signed: false\n");
  EXPECT_TRUE(starts_with(message, "tables/t.yaml:7:5: ")) << message;
  EXPECT_NE(message.find("duplicate"), std::string::npos) << message;
}

TEST(ParseDeviceTable, DuplicateFieldId) {
  const auto message = table_error(
      "id: t\n"
      "registers:\n"
      "  - { offset: 0x00, id: a, kind: analog, signed: false }\n"
      "  - { offset: 0x01, id: b, kind: bits, fields: [ { bits: \"0\", id: a } ] }\n");
  EXPECT_TRUE(starts_with(message, "tables/t.yaml:4:5: ")) << message;
  EXPECT_NE(message.find("'a'"), std::string::npos) << message;
}

TEST(ParseDeviceTable, OffsetOutOfOrder) {
  const auto message = table_error(
      "id: t\n"
      "registers:\n"
      "  - offset: 0x00\n"
      "    id: a\n"
      "    kind: analog\n"
      "    signed: false\n"
      "  - offset: 0x02\n"
      "    id: b\n"
      "    kind: analog\n"
      "    signed: false\n");
  EXPECT_TRUE(starts_with(message, "tables/t.yaml:7:5: ")) << message;
  EXPECT_NE(message.find("0x02"), std::string::npos) << message;
}

TEST(ParseDeviceTable, U32LowWithoutItsHigh) {
  const auto message = table_error(
      "id: t\n"
      "registers:\n"
      "  - offset: 0x00\n"
      "    id: energy_low\n"
      "    kind: u32_low\n"
      "    pair: energy\n"
      "  - offset: 0x01\n"
      "    id: power\n"
      "    kind: analog\n"
      "    signed: false\n");
  EXPECT_TRUE(starts_with(message, "tables/t.yaml:3:5: ")) << message;
  EXPECT_NE(message.find("energy_low"), std::string::npos) << message;
}

TEST(ParseDeviceTable, U32LowAsTheLastRegister) {
  const auto message = table_error(
      "id: t\n"
      "registers:\n"
      "  - { offset: 0x00, id: power, kind: analog, signed: false }\n"
      "  - { offset: 0x01, id: energy_low, kind: u32_low, pair: energy }\n");
  EXPECT_TRUE(starts_with(message, "tables/t.yaml:4:5: ")) << message;
}

TEST(ParseDeviceTable, FieldsOnAnAnalogRegister) {
  const auto message = table_error(
      "id: t\n"
      "registers:\n"
      "  - offset: 0x00\n"
      "    id: a\n"
      "    kind: analog\n"
      "    signed: false\n"
      "    fields: [ { bits: \"0\", id: f } ]\n");
  EXPECT_TRUE(starts_with(message, "tables/t.yaml:7:13: ")) << message;
  EXPECT_NE(message.find("analog"), std::string::npos) << message;
}

TEST(ParseDeviceTable, AnAnalogRegisterSaysWhetherItIsSigned) {
  const auto missing = table_error(
      "id: t\n"
      "registers:\n"
      "  - { offset: 0x00, id: power, kind: analog, unit: kW, scale: 0.1 }\n");
  EXPECT_TRUE(starts_with(missing, "tables/t.yaml:3:5: ")) << missing;
  EXPECT_NE(missing.find("'power' needs 'signed: true' or 'signed: false'"), std::string::npos) << missing;
  const auto on_bits = table_error(
      "id: t\n"
      "registers:\n"
      "  - { offset: 0x00, id: status, kind: bits, signed: true }\n");
  EXPECT_TRUE(starts_with(on_bits, "tables/t.yaml:3:53: ")) << on_bits;
  const auto t = parse_device_table(
      "id: t\n"
      "registers:\n"
      "  - { offset: 0x00, id: temperature, kind: analog, signed: true, unit: \"°C\", scale: 0.1 }\n"
      "  - { offset: 0x01, id: speed, kind: analog, signed: false, unit: min-1, scale: 1 }\n",
      "t.yaml");
  EXPECT_TRUE(t.registers[0].is_signed);
  EXPECT_FALSE(t.registers[1].is_signed);
}

TEST(ParseDeviceTable, TheBytesOfAPairHaveUnitsOfTheirOwnAndVariantsAreRecorded) {
  const auto t = parse_device_table(
      "id: t\n"
      "registers:\n"
      "  - offset: 0x00\n"
      "    id: knock_rank\n"
      "    kind: byte_pair\n"
      "    only: \"UIS3\"\n"
      "    fields:\n"
      "      - { bits: \"0-7\", id: cylinder }\n"
      "      - { bits: \"8-15\", id: level, unit: \"%\", scale: 0.78125, only: \"UIS3\" }\n",
      "t.yaml");
  const auto& reg = t.registers[0];
  EXPECT_EQ(reg.only, "UIS3");
  EXPECT_EQ(reg.fields[0].unit, "");
  EXPECT_DOUBLE_EQ(reg.fields[0].scale, 1.0);
  EXPECT_EQ(reg.fields[1].unit, "%");
  EXPECT_DOUBLE_EQ(reg.fields[1].scale, 0.78125);
  EXPECT_EQ(reg.fields[1].only, "UIS3");
  const auto on_bits = table_error(
      "id: t\n"
      "registers:\n"
      "  - { offset: 0x00, id: status, kind: bits, fields: [ { bits: \"0\", id: run, unit: \"%\" } ] }\n");
  EXPECT_NE(on_bits.find("only in a byte_pair"), std::string::npos) << on_bits;
}

TEST(ParseDeviceTable, BadBits) {
  const auto message = table_error(
      "id: t\n"
      "registers:\n"
      "  - offset: 0x00\n"
      "    id: a\n"
      "    kind: bits\n"
      "    fields:\n"
      "      - { bits: \"16\", id: f }\n");
  EXPECT_TRUE(starts_with(message, "tables/t.yaml:7:17: ")) << message;
  EXPECT_NE(message.find("16"), std::string::npos) << message;
  // A reversed range is refused too.
  const auto reversed = table_error(
      "id: t\n"
      "registers:\n"
      "  - { offset: 0x00, id: a, kind: bits, fields: [ { bits: \"5-3\", id: f } ] }\n");
  EXPECT_TRUE(starts_with(reversed, "tables/t.yaml:3:")) << reversed;
}

TEST(ParseDeviceTable, YamlSyntaxError) {
  const auto message = table_error("id: t\nregisters: [ x }\n");
  EXPECT_TRUE(starts_with(message, "tables/t.yaml:2:16: ")) << message;
}

// ---------------------------------------------------------------------------------------
// offline values

TEST(OfflineValue, PerKind) {
  EXPECT_EQ(offline_value(RegisterKind::analog), 0x7FFF);
  EXPECT_EQ(offline_value(RegisterKind::bits), 0x0000);
  EXPECT_EQ(offline_value(RegisterKind::byte_pair), 0xFFFF);
  EXPECT_EQ(offline_value(RegisterKind::ascii_pair), 0x2020);
  EXPECT_EQ(not_measured, 0x7FFF);
}

}  // namespace
}  // namespace unima::banks
