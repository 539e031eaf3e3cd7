// The register space (SPEC §1, §2): bank ids and default bases, the address map, the
// embedded device tables and their parser, the register store and the Modbus view of it.

#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "banks/address_map.hpp"
#include "banks/bank_id.hpp"
#include "banks/device_table.hpp"
#include "banks/embedded_tables.hpp"
#include "banks/register_space.hpp"
#include "banks/register_store.hpp"
#include "banks/table_catalog.hpp"
#include "tests/support/error_message.hpp"

namespace unima::banks {
namespace {

// ---------------------------------------------------------------------------------------
// bank_id

TEST(BankId, DefaultBasesFollowTheSeed) {
  EXPECT_EQ(default_base(BankId::A), 0x1000);
  EXPECT_EQ(default_base(BankId::B), 0x1010);
  EXPECT_EQ(default_base(BankId::C), 0x1020);
  EXPECT_EQ(default_base(BankId::D1), 0x1100);
  EXPECT_EQ(default_base(BankId::D2), 0x1200);
  EXPECT_EQ(default_base(BankId::D3), 0x1300);
  EXPECT_EQ(default_base(BankId::D4), 0x1400);
  EXPECT_EQ(default_base(BankId::S1), 0x2100);
  EXPECT_EQ(default_base(BankId::S2), 0x2200);
  EXPECT_EQ(default_base(BankId::S3), 0x2300);
  EXPECT_EQ(default_base(BankId::S4), 0x2400);
  EXPECT_EQ(default_base(BankId::S5), 0x2500);
  EXPECT_EQ(default_base(BankId::S6), 0x2600);
  EXPECT_EQ(default_base(BankId::S7), 0x2700);
  EXPECT_EQ(default_base(BankId::W), 0x3000);
  EXPECT_EQ(default_base(BankId::X), 0x3010);
}

TEST(BankId, NamesRoundTrip) {
  const std::array<std::string_view, bank_count> expected = {"A",  "B",  "C",  "D1", "D2", "D3", "D4", "S1",
                                                            "S2", "S3", "S4", "S5", "S6", "S7", "W",  "X"};
  for (std::size_t i = 0; i < bank_count; ++i) {
    const BankId bank = all_banks[i];
    EXPECT_EQ(index_of(bank), i);
    EXPECT_EQ(bank_name(bank), expected[i]);
    const auto parsed = parse_bank_name(bank_name(bank));
    ASSERT_TRUE(parsed.has_value()) << expected[i];
    EXPECT_EQ(*parsed, bank);
  }
}

TEST(BankId, UnknownNamesAreRejected) {
  for (std::string_view name : {"", "D", "D0", "D5", "S0", "S8", "d1", "a", "w", "AA", "Y", "C1", " A", "A "})
    EXPECT_FALSE(parse_bank_name(name).has_value()) << "'" << name << "'";
}

TEST(BankId, NumbersAndKinds) {
  EXPECT_EQ(bank_number(BankId::D1), 1u);
  EXPECT_EQ(bank_number(BankId::D4), 4u);
  EXPECT_EQ(bank_number(BankId::S1), 1u);
  EXPECT_EQ(bank_number(BankId::S7), 7u);
  EXPECT_EQ(bank_number(BankId::W), 0u);
  for (unsigned n = 1; n <= 4; ++n) EXPECT_EQ(bank_number(device_bank(n)), n);
  for (unsigned n = 1; n <= 7; ++n) EXPECT_EQ(bank_number(module_bank(n)), n);
  EXPECT_TRUE(is_device_bank(BankId::D3));
  EXPECT_FALSE(is_device_bank(BankId::S1));
  EXPECT_TRUE(is_module_bank(BankId::S7));
  EXPECT_FALSE(is_module_bank(BankId::D4));
  EXPECT_TRUE(is_write_bank(BankId::W));
  EXPECT_TRUE(is_write_bank(BankId::X));
  EXPECT_FALSE(is_write_bank(BankId::C));
}

// ---------------------------------------------------------------------------------------
// AddressMap

Window bank_window(BankId bank, std::uint16_t first, std::uint16_t count, std::string origin = {}) {
  Window w;
  w.kind = Window::Kind::bank;
  w.bank = bank;
  w.first = first;
  w.count = count;
  w.name = "bank " + std::string(bank_name(bank));
  w.origin = std::move(origin);
  return w;
}

TEST(AddressMap, FindsWindowsAtTheirFirstAndLastAddresses) {
  // Given out of order: the map sorts them.
  const AddressMap map({bank_window(BankId::C, 0x1020, 20), bank_window(BankId::A, 0x1000, 16),
                        bank_window(BankId::B, 0x1010, 1)});
  ASSERT_EQ(map.windows().size(), 3u);

  auto bank_at = [&](std::uint16_t address) -> std::optional<BankId> {
    const Window* w = map.find(address);
    if (!w) return std::nullopt;
    return w->bank;
  };
  EXPECT_EQ(bank_at(0x1000), BankId::A);
  EXPECT_EQ(bank_at(0x100F), BankId::A);
  EXPECT_EQ(bank_at(0x1010), BankId::B);
  EXPECT_EQ(bank_at(0x1020), BankId::C);
  EXPECT_EQ(bank_at(0x1033), BankId::C);
  EXPECT_EQ(bank_at(0x0000), std::nullopt);
  EXPECT_EQ(bank_at(0x0FFF), std::nullopt);
  EXPECT_EQ(bank_at(0x1011), std::nullopt);
  EXPECT_EQ(bank_at(0x101F), std::nullopt);
  EXPECT_EQ(bank_at(0x1034), std::nullopt);
  EXPECT_EQ(bank_at(0xFFFF), std::nullopt);
}

TEST(AddressMap, EmptyMapFindsNothing) {
  const AddressMap map;
  EXPECT_EQ(map.find(0), nullptr);
  EXPECT_EQ(map.find(0x1000), nullptr);
}

TEST(AddressMap, WindowAtTheTopOfTheAddressSpace) {
  const AddressMap map({bank_window(BankId::W, 0xFFF0, 16)});
  ASSERT_NE(map.find(0xFFFF), nullptr);
  EXPECT_EQ(map.find(0xFFFF)->bank, BankId::W);
  EXPECT_EQ(map.find(0xFFEF), nullptr);
}

TEST(AddressMap, AdjacentAfter) {
  const AddressMap map({bank_window(BankId::A, 0x1000, 16), bank_window(BankId::B, 0x1010, 1),
                        bank_window(BankId::C, 0x1020, 20)});
  const Window* a = map.find(0x1000);
  const Window* b = map.find(0x1010);
  const Window* c = map.find(0x1020);
  ASSERT_TRUE(a && b && c);
  EXPECT_EQ(map.adjacent_after(*a), b);   // B starts where A ends
  EXPECT_EQ(map.adjacent_after(*b), nullptr);  // a gap 0x1011..0x101F follows B
  EXPECT_EQ(map.adjacent_after(*c), nullptr);  // the last window
}

TEST(AddressMap, OverlapNamesBothWindowsWithTheirRanges) {
  try {
    AddressMap map({bank_window(BankId::D1, 0x0011, 64), bank_window(BankId::W, 0x0040, 16, "bridge.yaml:4:11")});
    FAIL() << "expected OverlapError";
  } catch (const OverlapError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("bank D1 (0x0011..0x0050)"), std::string::npos) << message;
    EXPECT_NE(message.find("bank W (0x0040..0x004F)"), std::string::npos) << message;
    EXPECT_EQ(message.rfind("bridge.yaml:4:11: ", 0), 0u) << message;
  }
}

TEST(AddressMap, OverlapMessageStartsWithTheOriginOfWhicheverWindowHasOne) {
  // Only the first (lower) window was set by the config.
  try {
    AddressMap map({bank_window(BankId::W, 0x3000, 16), bank_window(BankId::A, 0x2FF8, 16, "cfg.yaml:2:6")});
    FAIL() << "expected OverlapError";
  } catch (const OverlapError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("cfg.yaml:2:6: ", 0), 0u) << message;
    EXPECT_NE(message.find("bank A (0x2FF8..0x3007)"), std::string::npos) << message;
    EXPECT_NE(message.find("bank W (0x3000..0x300F)"), std::string::npos) << message;
  }
}

TEST(AddressMap, OverlapOfAWindowInsideAnother) {
  EXPECT_THROW(AddressMap({bank_window(BankId::D1, 0x1100, 64), bank_window(BankId::B, 0x1120, 1)}), OverlapError);
  // Touching is not overlapping.
  EXPECT_NO_THROW(AddressMap({bank_window(BankId::A, 0x1000, 16), bank_window(BankId::B, 0x1010, 1)}));
}

TEST(AddressMap, WindowRunningPastTheLastAddressThrows) {
  try {
    AddressMap map({bank_window(BankId::D2, 0xFFF0, 64, "bridge.yaml:7:9")});
    FAIL() << "expected OverlapError";
  } catch (const OverlapError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("bridge.yaml:7:9: ", 0), 0u) << message;
    EXPECT_NE(message.find("bank D2"), std::string::npos) << message;
    EXPECT_NE(message.find("0xFFFF"), std::string::npos) << message;
  }
  EXPECT_NO_THROW(AddressMap({bank_window(BankId::D2, 0xFFC0, 64)}));
  EXPECT_THROW(AddressMap({bank_window(BankId::D2, 0xFFC1, 64)}), OverlapError);
}

// ---------------------------------------------------------------------------------------
// The embedded tables

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

// ---------------------------------------------------------------------------------------
// parse_device_table

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

// ---------------------------------------------------------------------------------------
// RegisterStore

const DeviceTable& chp() {
  const DeviceTable* t = find_device_type("unigen-chp");
  if (!t) throw std::runtime_error("unigen-chp missing");
  return *t;
}

BankShapes shapes_with(std::array<const DeviceTable*, 4> devices) {
  return standard_shapes(devices, io_module_table(), bridge_internal_table());
}

std::uint16_t first_offset_of_kind(const DeviceTable& table, RegisterKind kind) {
  for (const auto& r : table.registers)
    if (r.kind == kind) return r.offset;
  throw std::runtime_error("no register of that kind");
}

TEST(RegisterStore, ShapesOfTheBanks) {
  const RegisterStore store(shapes_with({&chp(), nullptr, find_device_type("usc"), nullptr}));
  EXPECT_EQ(store.length(BankId::A), 16);
  EXPECT_EQ(store.length(BankId::B), 1);
  EXPECT_EQ(store.length(BankId::C), 20);
  EXPECT_EQ(store.length(BankId::W), 16);
  EXPECT_EQ(store.length(BankId::X), 1);
  for (unsigned n = 1; n <= 7; ++n) EXPECT_EQ(store.length(module_bank(n)), 20);
  EXPECT_EQ(store.length(BankId::D1), 64);
  EXPECT_TRUE(store.exists(BankId::D1));
  EXPECT_FALSE(store.exists(BankId::D2));
  EXPECT_EQ(store.length(BankId::D3), 0x28);
  EXPECT_FALSE(store.exists(BankId::D4));
  EXPECT_EQ(store.table(BankId::D1), &chp());
  EXPECT_EQ(store.table(BankId::D2), nullptr);
}

TEST(RegisterStore, OfflineDeviceReadsOfflineValuesEvenAfterATelegram) {
  RegisterStore store(shapes_with({&chp(), nullptr, nullptr, nullptr}));
  const auto& table = chp();
  auto expect_all_offline = [&] {
    for (const auto& r : table.registers)
      EXPECT_EQ(store.read(BankId::D1, r.offset), offline_value(r.kind)) << r.id;
  };
  expect_all_offline();
  std::vector<std::uint16_t> values(table.length());
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = static_cast<std::uint16_t>(0x0100 + i);
  EXPECT_TRUE(store.store_telegram(BankId::D1, 0, values));
  EXPECT_FALSE(store.online(BankId::D1));
  expect_all_offline();
  // On-line, the same registers show what the telegram carried.
  store.set_online(BankId::D1, true);
  for (std::size_t i = 0; i < values.size(); ++i) EXPECT_EQ(store.read(BankId::D1, static_cast<std::uint16_t>(i)), values[i]);
  // Off-line again: back to the off-line values.
  store.set_online(BankId::D1, false);
  expect_all_offline();
}

TEST(RegisterStore, OnlineDeviceReadsOnlyTheRegistersATelegramCarried) {
  RegisterStore store(shapes_with({&chp(), nullptr, nullptr, nullptr}));
  const auto& table = chp();
  store.set_online(BankId::D1, true);
  const std::vector<std::uint16_t> values = {853, 854};
  EXPECT_TRUE(store.store_telegram(BankId::D1, 0x21, values));
  EXPECT_EQ(store.read(BankId::D1, 0x21), 853);
  EXPECT_EQ(store.read(BankId::D1, 0x22), 854);
  for (const auto& r : table.registers) {
    if (r.offset == 0x21 || r.offset == 0x22) continue;
    EXPECT_EQ(store.read(BankId::D1, r.offset), offline_value(r.kind)) << r.id;
  }
  // A bit register not yet carried reads 0; an analog one 0x7FFF.
  EXPECT_EQ(store.read(BankId::D1, first_offset_of_kind(table, RegisterKind::bits)), 0);
  EXPECT_EQ(store.read(BankId::D1, first_offset_of_kind(table, RegisterKind::analog)), 0x7FFF);
  // The span read agrees with single reads.
  std::array<std::uint16_t, 4> out{};
  store.read(BankId::D1, 0x20, out);
  EXPECT_EQ(out[0], offline_value(table.registers[0x20].kind));
  EXPECT_EQ(out[1], 853);
  EXPECT_EQ(out[2], 854);
  EXPECT_EQ(out[3], offline_value(table.registers[0x23].kind));
}

TEST(RegisterStore, BitRegistersReadZeroOffline) {
  RegisterStore store(shapes_with({&chp(), nullptr, nullptr, nullptr}));
  const auto bits = first_offset_of_kind(chp(), RegisterKind::bits);
  const std::vector<std::uint16_t> v = {0xFFFF};
  store.store_telegram(BankId::D1, bits, v);
  EXPECT_EQ(store.read(BankId::D1, bits), 0);
  store.set_online(BankId::D1, true);
  EXPECT_EQ(store.read(BankId::D1, bits), 0xFFFF);
  store.set_online(BankId::D1, false);
  EXPECT_EQ(store.read(BankId::D1, bits), 0);
}

TEST(RegisterStore, ATelegramRunningPastTheEndStoresNothing) {
  RegisterStore store(shapes_with({&chp(), nullptr, nullptr, nullptr}));
  store.set_online(BankId::D1, true);
  const std::vector<std::uint16_t> values = {1, 2, 3};
  const auto before = std::array{store.read(BankId::D1, 62), store.read(BankId::D1, 63)};
  EXPECT_FALSE(store.store_telegram(BankId::D1, 62, values));  // 62, 63, and one past the end
  EXPECT_EQ((std::array{store.read(BankId::D1, 62), store.read(BankId::D1, 63)}), before);
  EXPECT_FALSE(store.store_telegram(BankId::D1, 64, values));
  EXPECT_FALSE(store.store_telegram(BankId::D2, 0, values));  // no D2 configured
}

TEST(RegisterStore, ModuleBanks) {
  RegisterStore store(shapes_with({nullptr, nullptr, nullptr, nullptr}));
  const DeviceTable& io = *io_module_table();
  for (const auto& r : io.registers) EXPECT_EQ(store.read(BankId::S3, r.offset), offline_value(r.kind)) << r.id;
  const std::vector<std::uint16_t> values = {11, 12};
  store.store_telegram(BankId::S3, 0, values);
  EXPECT_EQ(store.read(BankId::S3, 0), offline_value(io.registers[0].kind));
  store.set_online(BankId::S3, true);
  EXPECT_EQ(store.read(BankId::S3, 0), 11);
  EXPECT_EQ(store.read(BankId::S3, 1), 12);
  EXPECT_EQ(store.read(BankId::S4, 0), offline_value(io.registers[0].kind));
}

TEST(RegisterStore, InitialValuesOfTheFixedBanks) {
  const RegisterStore store(shapes_with({nullptr, nullptr, nullptr, nullptr}));
  for (std::uint16_t i = 0; i < 16; ++i) {
    EXPECT_EQ(store.read(BankId::W, i), 0x7FFF) << i;
    EXPECT_EQ(store.read(BankId::A, i), 0x7FFF) << i;
    EXPECT_EQ(store.read(BankId::C, i), 0x7FFF) << i;  // user analog outputs not yet set
  }
  EXPECT_EQ(store.read(BankId::X, 0), 0);
  EXPECT_EQ(store.read(BankId::B, 0), 0);
  EXPECT_EQ(store.read(BankId::C, c_bank::user_binary_inputs), 0);
  EXPECT_EQ(store.read(BankId::C, c_bank::user_binary_outputs), 0);
  EXPECT_EQ(store.read(BankId::C, c_bank::online_bits), 0);
}

struct Change {
  BankId bank;
  std::uint16_t offset;
  std::uint16_t value;
  bool operator==(const Change&) const = default;
};

TEST(RegisterStore, WriteNotifiesTheListener) {
  RegisterStore store(shapes_with({nullptr, nullptr, nullptr, nullptr}));
  std::vector<Change> changes;
  store.set_change_listener([&](BankId b, std::uint16_t o, std::uint16_t v) { changes.push_back({b, o, v}); });
  store.write(BankId::W, 3, 1234);
  store.write(BankId::X, 0, 0x0005);
  EXPECT_EQ(store.read(BankId::W, 3), 1234);
  EXPECT_EQ(store.read(BankId::W, 2), 0x7FFF);
  EXPECT_EQ(store.read(BankId::X, 0), 5);
  const std::vector<Change> expected = {{BankId::W, 3, 1234}, {BankId::X, 0, 5}};
  EXPECT_EQ(changes, expected);
}

TEST(RegisterStore, UserOutputNIsCPlusNMinusOne) {
  RegisterStore store(shapes_with({nullptr, nullptr, nullptr, nullptr}));
  std::vector<Change> changes;
  store.set_change_listener([&](BankId b, std::uint16_t o, std::uint16_t v) { changes.push_back({b, o, v}); });
  store.set_user_output(1, 100);
  store.set_user_output(3, 300);
  store.set_user_output(16, 1600);
  EXPECT_EQ(store.read(BankId::C, 0), 100);
  EXPECT_EQ(store.read(BankId::C, 1), 0x7FFF);
  EXPECT_EQ(store.read(BankId::C, 2), 300);
  EXPECT_EQ(store.read(BankId::C, 15), 1600);
  EXPECT_EQ(store.read(BankId::C, 0x10), 0);  // not spilled into the user binary inputs
  const std::vector<Change> expected = {{BankId::C, 0, 100}, {BankId::C, 2, 300}, {BankId::C, 15, 1600}};
  EXPECT_EQ(changes, expected);
}

TEST(RegisterStore, OnlineBits) {
  RegisterStore store(shapes_with({&chp(), &chp(), &chp(), &chp()}));
  EXPECT_EQ(store.online_bits(), 0);
  for (unsigned n = 1; n <= 4; ++n) {
    store.set_online(device_bank(n), true);
    EXPECT_EQ(store.online_bits(), 1u << (n - 1)) << "D" << n;
    EXPECT_EQ(store.read(BankId::C, c_bank::online_bits), 1u << (n - 1)) << "D" << n;
    store.set_online(device_bank(n), false);
  }
  for (unsigned n = 1; n <= 7; ++n) {
    store.set_online(module_bank(n), true);
    EXPECT_EQ(store.online_bits(), 1u << (7 + n)) << "S" << n;
    EXPECT_EQ(store.read(BankId::C, c_bank::online_bits), 1u << (7 + n)) << "S" << n;
    store.set_online(module_bank(n), false);
  }
  store.set_modbus_error(true);
  EXPECT_EQ(store.online_bits(), 0x8000);
  EXPECT_EQ(store.read(BankId::C, 0x13), 0x8000);
  store.set_modbus_error(false);
  EXPECT_EQ(store.read(BankId::C, 0x13), 0);

  store.set_online(BankId::D1, true);
  store.set_online(BankId::D3, true);
  store.set_online(BankId::S2, true);
  store.set_online(BankId::S7, true);
  store.set_modbus_error(true);
  EXPECT_EQ(store.read(BankId::C, 0x13), 0x0001 | 0x0004 | 0x0200 | 0x4000 | 0x8000);
  // Read as part of a span of C too.
  std::array<std::uint16_t, 2> out{};
  store.read(BankId::C, 0x12, out);
  EXPECT_EQ(out[1], 0xC205);
}

TEST(RegisterStore, TakeStateFromCarriesPublishedValuesAndSameTableDevices) {
  const DeviceTable* uvr = find_device_type("uvr");
  ASSERT_NE(uvr, nullptr);
  RegisterStore old(shapes_with({&chp(), &chp(), nullptr, nullptr}));
  old.write(BankId::W, 0, 42);
  old.write(BankId::W, 15, 4242);
  old.write(BankId::X, 0, 0x0101);
  old.set_user_output(5, 555);
  const std::vector<std::uint16_t> values = {853, 854};
  old.store_telegram(BankId::D1, 0x21, values);
  old.store_telegram(BankId::D2, 0x21, values);
  old.set_online(BankId::D1, true);
  old.set_online(BankId::D2, true);

  // D1 keeps its table, D2 changes type.
  RegisterStore fresh(shapes_with({&chp(), uvr, nullptr, nullptr}));
  std::vector<Change> changes;
  fresh.set_change_listener([&](BankId b, std::uint16_t o, std::uint16_t v) { changes.push_back({b, o, v}); });
  fresh.take_state_from(old);

  EXPECT_EQ(fresh.read(BankId::W, 0), 42);
  EXPECT_EQ(fresh.read(BankId::W, 15), 4242);
  EXPECT_EQ(fresh.read(BankId::W, 1), 0x7FFF);
  EXPECT_EQ(fresh.read(BankId::X, 0), 0x0101);
  EXPECT_EQ(fresh.read(BankId::C, 4), 555);
  fresh.set_online(BankId::D1, true);
  EXPECT_EQ(fresh.read(BankId::D1, 0x21), 853);
  EXPECT_EQ(fresh.read(BankId::D1, 0x22), 854);
  EXPECT_EQ(fresh.read(BankId::D1, 0x20), offline_value(chp().registers[0x20].kind));
  // The new D2 table is another device: nothing of the old values.
  EXPECT_EQ(fresh.length(BankId::D2), uvr->length());
  fresh.set_online(BankId::D2, true);
  EXPECT_EQ(fresh.read(BankId::D2, 0x21), offline_value(uvr->registers[0x21].kind));
  EXPECT_EQ(fresh.read(BankId::D2, 0x22), offline_value(uvr->registers[0x22].kind));
  // The old store's listener is untouched, the fresh store's still works.
  fresh.write(BankId::W, 1, 7);
  ASSERT_FALSE(changes.empty());
  EXPECT_EQ(changes.back(), (Change{BankId::W, 1, 7}));
}

// ---------------------------------------------------------------------------------------
// RegisterSpace

struct SpaceFixture : ::testing::Test {
  SpaceFixture() : store(shapes_with({&chp(), nullptr, nullptr, nullptr})) {}

  AddressMap standard_map() const {
    return AddressMap({bank_window(BankId::A, 0x1000, 16), bank_window(BankId::B, 0x1010, 1),
                       bank_window(BankId::C, 0x1020, 20), bank_window(BankId::D1, 0x1100, 64),
                       bank_window(BankId::S1, 0x2100, 20), bank_window(BankId::W, 0x3000, 16),
                       bank_window(BankId::X, 0x3010, 1)});
  }
  RegisterSpace space(bool readable_write_banks = true) {
    return RegisterSpace(standard_map(), store, AccessRules{readable_write_banks});
  }

  RegisterStore store;
};

TEST_F(SpaceFixture, ReadSpanningTwoAdjacentBanks) {
  auto s = space();
  std::array<std::uint16_t, 2> out = {0xAAAA, 0xAAAA};
  ASSERT_TRUE(s.read(0x100F, out));
  EXPECT_EQ(out[0], 0x7FFF);  // A+15
  EXPECT_EQ(out[1], 0x0000);  // B+0

  store.write(BankId::W, 15, 0x1234);
  store.write(BankId::X, 0, 0x0005);
  ASSERT_TRUE(s.read(0x300F, out));
  EXPECT_EQ(out[0], 0x1234);
  EXPECT_EQ(out[1], 0x0005);

  std::array<std::uint16_t, 17> all{};
  ASSERT_TRUE(s.read(0x1000, all));
  for (std::size_t i = 0; i < 16; ++i) EXPECT_EQ(all[i], 0x7FFF) << i;
  EXPECT_EQ(all[16], 0);
}

TEST_F(SpaceFixture, ReadOfABankInTheMiddle) {
  auto s = space();
  store.set_online(BankId::D1, true);
  const std::vector<std::uint16_t> values = {853, 854};
  store.store_telegram(BankId::D1, 0x21, values);
  std::array<std::uint16_t, 2> out{};
  ASSERT_TRUE(s.read(0x1121, out));
  EXPECT_EQ(out[0], 853);
  EXPECT_EQ(out[1], 854);
  std::array<std::uint16_t, 1> last{};
  ASSERT_TRUE(s.read(0x113F, last));
  EXPECT_EQ(last[0], offline_value(chp().registers[63].kind));
}

TEST_F(SpaceFixture, ReadTouchingAGapFails) {
  auto s = space();
  std::array<std::uint16_t, 2> two{};
  std::array<std::uint16_t, 1> one{};
  EXPECT_FALSE(s.read(0x1033, two));   // C+0x13 then the gap at 0x1034
  EXPECT_FALSE(s.read(0x1010, two));   // B then the gap at 0x1011
  EXPECT_FALSE(s.read(0x0FFF, two));   // the gap before A
  EXPECT_FALSE(s.read(0x1034, one));
  EXPECT_FALSE(s.read(0x1140, one));   // just past D1
  EXPECT_FALSE(s.read(0x1200, one));   // D2 does not exist
  EXPECT_TRUE(s.read(0x1033, one));
  EXPECT_TRUE(s.read(0x113F, one));
  std::array<std::uint16_t, 64> d1{};
  EXPECT_TRUE(s.read(0x1100, d1));
  std::array<std::uint16_t, 65> past_d1{};
  EXPECT_FALSE(s.read(0x1100, past_d1));
}

TEST_F(SpaceFixture, ReadingTheWriteBanksFollowsTheRule) {
  store.write(BankId::W, 0, 99);
  std::array<std::uint16_t, 1> out{};
  {
    auto s = space(false);
    EXPECT_FALSE(s.read(0x3000, out));
    EXPECT_FALSE(s.read(0x3010, out));
    std::array<std::uint16_t, 2> span{};
    EXPECT_FALSE(s.read(0x300F, span));
    EXPECT_TRUE(s.read(0x1000, out));  // other banks are still readable
  }
  {
    auto s = space(true);
    ASSERT_TRUE(s.read(0x3000, out));
    EXPECT_EQ(out[0], 99);
    ASSERT_TRUE(s.read(0x3010, out));
    EXPECT_EQ(out[0], 0);
  }
}

TEST_F(SpaceFixture, ReadOfCountZeroFails) {
  auto s = space();
  std::span<std::uint16_t> no_out;
  EXPECT_FALSE(s.read(0x1000, no_out));
}

TEST(RegisterSpace, RangesRunningPastTheTopOfTheAddressSpaceFail) {
  RegisterStore store(shapes_with({nullptr, nullptr, nullptr, nullptr}));
  RegisterSpace s(AddressMap({bank_window(BankId::W, 0xFFF0, 16)}), store, AccessRules{});
  std::array<std::uint16_t, 16> sixteen{};
  EXPECT_TRUE(s.read(0xFFF0, sixteen));
  std::array<std::uint16_t, 2> two{};
  EXPECT_FALSE(s.read(0xFFFF, two));
}

}  // namespace
}  // namespace unima::banks
