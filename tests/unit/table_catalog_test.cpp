// The embedded device tables (SPEC §2): all eleven load, are found by id, alias and head,
// and are well formed — checked through the parser and straight on their YAML text.

#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "banks/bank_id.hpp"
#include "banks/device_table.hpp"
#include "banks/embedded_tables.hpp"
#include "banks/table_catalog.hpp"

namespace unima::banks {
namespace {

TEST(TableCatalog, AllElevenTablesLoad) {
  const auto tables = all_tables();
  std::set<std::string> ids;
  for (const auto* t : tables) ids.insert(t->id);
  const std::set<std::string> expected = {"bridge-internal", "bridge-tem", "io-module", "microgen-sync",
                                          "nsu2",            "uis",        "unigen-chp", "unigen-mve",
                                          "unigen-tem",      "usc",        "uvr"};
  EXPECT_EQ(tables.size(), 11u);
  EXPECT_EQ(ids, expected);
  EXPECT_EQ(embedded_tables().size(), 11u);
}

// The catalog finds a table by its head and parses the rest on first use: the table it
// hands out is the one all_tables() lists later, and each embedded head names its table.
TEST(TableCatalog, ATableFoundByItsHeadIsTheParsedTable) {
  const DeviceTable* by_alias = find_device_type("microgen-chp");
  ASSERT_NE(by_alias, nullptr);
  EXPECT_EQ(by_alias->id, "unigen-chp");
  EXPECT_EQ(find_device_type("unigen-chp"), by_alias);
  const auto tables = all_tables();
  EXPECT_NE(std::find(tables.begin(), tables.end(), by_alias), tables.end());
  for (const auto& embedded : embedded_tables()) {
    const auto head = parse_device_table_head(embedded.yaml_text, embedded.file_name);
    const auto full = parse_device_table(embedded.yaml_text, embedded.file_name);
    EXPECT_EQ(head.id, full.id);
    EXPECT_EQ(head.aliases, full.aliases);
  }
}

TEST(TableCatalog, DeviceTypesAreTheNineOfSpec2) {
  auto ids = device_type_ids();
  std::vector<std::string> got(ids.begin(), ids.end());
  std::sort(got.begin(), got.end());
  const std::vector<std::string> expected = {"bridge-tem", "microgen-sync", "nsu2",       "uis", "unigen-chp",
                                             "unigen-mve", "unigen-tem",    "usc",        "uvr"};
  EXPECT_EQ(got, expected);
  for (const auto& id : expected) {
    const DeviceTable* t = find_device_type(id);
    ASSERT_NE(t, nullptr) << id;
    EXPECT_EQ(t->id, id);
  }
  // The S_N and C tables are not device types a D_N bank can select.
  EXPECT_EQ(find_device_type("io-module"), nullptr);
  EXPECT_EQ(find_device_type("bridge-internal"), nullptr);
  EXPECT_EQ(find_device_type("unigen"), nullptr);
  EXPECT_EQ(find_device_type(""), nullptr);
  EXPECT_EQ(find_device_type("UNIGEN-CHP"), nullptr);
}

TEST(TableCatalog, AliasesFindTheirTable) {
  const DeviceTable* chp = find_device_type("microgen-chp");
  ASSERT_NE(chp, nullptr);
  EXPECT_EQ(chp->id, "unigen-chp");
  EXPECT_EQ(chp, find_device_type("unigen-chp"));
  const DeviceTable* mve = find_device_type("microgen-mve");
  ASSERT_NE(mve, nullptr);
  EXPECT_EQ(mve->id, "unigen-mve");
  EXPECT_EQ(mve, find_device_type("unigen-mve"));
}

TEST(TableCatalog, IoModuleAndBridgeInternalTables) {
  ASSERT_NE(io_module_table(), nullptr);
  EXPECT_EQ(io_module_table()->id, io_module_table_id);
  EXPECT_EQ(io_module_table()->length(), s_bank_length);
  ASSERT_NE(bridge_internal_table(), nullptr);
  EXPECT_EQ(bridge_internal_table()->id, bridge_internal_table_id);
  EXPECT_EQ(bridge_internal_table()->length(), c_bank_length);
}

TEST(TableCatalog, UscHasExactly0x28Registers) {
  const DeviceTable* usc = find_device_type("usc");
  ASSERT_NE(usc, nullptr);
  EXPECT_EQ(usc->length(), 0x28);
}

TEST(TableCatalog, UnigenChpOilTemperature) {
  const DeviceTable* chp = find_device_type("unigen-chp");
  ASSERT_NE(chp, nullptr);
  EXPECT_EQ(chp->length(), 64);
  const RegisterDef* oil = chp->find("oil_temperature");
  ASSERT_NE(oil, nullptr);
  EXPECT_EQ(oil->offset, 0x21);
  EXPECT_EQ(oil->unit, "°C");
  EXPECT_DOUBLE_EQ(oil->scale, 0.1);
  EXPECT_EQ(oil->kind, RegisterKind::analog);
  EXPECT_EQ(&chp->registers[0x21], oil);
  EXPECT_EQ(chp->find("no_such_register"), nullptr);
}

// Seed §6.2.4.6: the cylinder masks are bits (an off-line UIS reads 0 there, like any bit
// register); in a knock rank only the level byte is in 0.78125 %, the other is a cylinder.
TEST(TableCatalog, UisMasksAreBitsAndTheKnockRankBytesHaveTheirOwnUnits) {
  const DeviceTable* uis = find_device_type("uis");
  ASSERT_NE(uis, nullptr);
  for (std::uint16_t offset : {0x0C, 0x0D}) {
    EXPECT_EQ(uis->registers[offset].kind, RegisterKind::bits) << offset;
    EXPECT_EQ(offline_value(uis->registers[offset].kind), 0) << offset;
    EXPECT_EQ(uis->registers[offset].only, "UIS1");
  }
  for (std::uint16_t offset : {0x08, 0x09, 0x0A}) {
    const auto& rank = uis->registers[offset];
    ASSERT_EQ(rank.fields.size(), 2u);
    EXPECT_EQ(rank.fields[0].unit, "") << rank.fields[0].id;
    EXPECT_DOUBLE_EQ(rank.fields[0].scale, 1.0);
    EXPECT_EQ(rank.fields[1].unit, "%") << rank.fields[1].id;
    EXPECT_DOUBLE_EQ(rank.fields[1].scale, 0.78125);
    EXPECT_EQ(rank.only, "UIS3");
  }
  EXPECT_EQ(uis->registers[0x28].fields[1].scale, 0.78125);  // firing success: both bytes in %
  EXPECT_EQ(uis->registers[0x3C].only, "UIS4");
}

TEST(TableCatalog, TheSeedsVariantFootnotesAreRecorded) {
  const DeviceTable* chp = find_device_type("unigen-chp");
  ASSERT_NE(chp, nullptr);
  std::set<std::string> only_unigen;
  for (const auto& reg : chp->registers)
    for (const auto& field : reg.fields)
      if (field.only == "UniGEN-CHP") only_unigen.insert(field.id);
  EXPECT_EQ(only_unigen, (std::set<std::string>{"user_generator_contactor_control", "full_power_request",
                                                "stepper_motor_closed", "user_external_start"}));
  const auto mve = find_device_type("unigen-mve");
  ASSERT_NE(mve, nullptr);
  const auto& inputs = mve->registers[0x12].fields;
  const auto stepper = std::find_if(inputs.begin(), inputs.end(), [](const Field& f) { return f.id == "stepper_motor_closed"; });
  ASSERT_NE(stepper, inputs.end());
  EXPECT_EQ(stepper->only, "UniGEN-MVE");
}

TEST(TableCatalog, EveryAnalogRegisterSaysItsSign) {
  const DeviceTable* chp = find_device_type("unigen-chp");
  ASSERT_NE(chp, nullptr);
  EXPECT_TRUE(chp->find("oil_temperature")->is_signed);
  EXPECT_TRUE(chp->find("mains_active_power")->is_signed);
  EXPECT_FALSE(chp->find("engine_speed")->is_signed);
}

TEST(TableCatalog, EveryTableIsWellFormed) {
  for (const auto* table : all_tables()) {
    const auto& t = *table;
    SCOPED_TRACE(t.id);
    EXPECT_GT(t.length(), 0);
    EXPECT_LE(t.length(), max_table_length);
    std::set<std::string> ids;
    for (std::size_t i = 0; i < t.registers.size(); ++i) {
      const auto& r = t.registers[i];
      EXPECT_EQ(r.offset, i) << r.id;
      EXPECT_FALSE(r.id.empty()) << "offset " << i;
      EXPECT_TRUE(ids.insert(r.id).second) << "duplicate " << r.id;
      for (const auto& f : r.fields) {
        EXPECT_TRUE(ids.insert(f.id).second) << "duplicate field " << f.id;
        EXPECT_LE(f.first_bit, f.last_bit) << f.id;
        EXPECT_LE(f.last_bit, 15) << f.id;
      }
      if (r.kind == RegisterKind::u32_low) {
        ASSERT_LT(i + 1, t.registers.size()) << r.id;
        EXPECT_EQ(t.registers[i + 1].kind, RegisterKind::u32_high) << r.id;
        EXPECT_EQ(t.registers[i + 1].pair, r.pair) << r.id;
      }
      if (r.kind == RegisterKind::u32_high) {
        ASSERT_GT(i, 0u);
        EXPECT_EQ(t.registers[i - 1].kind, RegisterKind::u32_low) << r.id;
      }
    }
  }
}

// The same checks straight on the YAML text, not trusting the table parser.
TEST(TableCatalog, EmbeddedYamlIsConsecutiveAndUniqueWhenReadIndependently) {
  for (const auto& embedded : embedded_tables()) {
    SCOPED_TRACE(std::string(embedded.file_name));
    const YAML::Node root = YAML::Load(std::string(embedded.yaml_text));
    ASSERT_TRUE(root["id"]);
    EXPECT_EQ(root["id"].as<std::string>() + ".yaml", std::string(embedded.file_name));
    const YAML::Node regs = root["registers"];
    ASSERT_TRUE(regs.IsSequence());
    EXPECT_GE(regs.size(), 1u);
    EXPECT_LE(regs.size(), 64u);
    std::set<std::string> ids;
    for (std::size_t i = 0; i < regs.size(); ++i) {
      const YAML::Node r = regs[i];
      const std::string offset = r["offset"].Scalar();
      ASSERT_EQ(offset.rfind("0x", 0), 0u) << offset;
      EXPECT_EQ(std::stoul(offset.substr(2), nullptr, 16), i) << offset;
      const std::string id = r["id"].Scalar();
      EXPECT_TRUE(ids.insert(id).second) << "duplicate " << id;
      if (r["fields"]) {
        for (const auto& f : r["fields"])
          EXPECT_TRUE(ids.insert(f["id"].Scalar()).second) << "duplicate field " << f["id"].Scalar();
      }
    }
  }
}

}  // namespace
}  // namespace unima::banks
