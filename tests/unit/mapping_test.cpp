// Issue #3 in the core: source references, mapping of A/B/C, read and write blocks, the
// register map, and the generated register reference.

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <tuple>
#include <sstream>

#include <fmt/format.h>

#include "banks/register_space.hpp"
#include "banks/write_path.hpp"
#include "banks/table_catalog.hpp"
#include "banks/table_reference.hpp"
#include "config/register_map.hpp"
#include "config/source_ref_parser.hpp"
#include "tests/support/error_message.hpp"

namespace unima {
namespace {

using banks::BankId;
using config::SourceUse;

const std::string devices_yaml =
    "devices:\n"
    "  D1: { type: unigen-chp, address: 5 }\n"
    "  D2: { type: uvr, address: 6 }\n"
    "  D3: { type: usc, address: 7 }\n"
    "  D4: { type: nsu2, address: 8 }\n";

config::Config load(const std::string& yaml) { return config::load_text(yaml, "t.yaml"); }

banks::BankShapes shapes() { return config::bank_shapes(load(devices_yaml)); }

banks::SourceRef ref(std::string_view text, SourceUse use) {
  auto parsed = config::parse_source_ref(text, shapes(), use);
  if (auto* error = std::get_if<std::string>(&parsed)) ADD_FAILURE() << *error;
  return std::get<banks::SourceRef>(parsed);
}

std::string ref_error(std::string_view text, SourceUse use) {
  auto parsed = config::parse_source_ref(text, shapes(), use);
  if (std::holds_alternative<banks::SourceRef>(parsed)) return "(parsed)";
  return std::get<std::string>(parsed);
}

TEST(SourceRef, EveryFormOfTheSpec) {
  auto r = ref("D1+0x21", SourceUse::analog);
  EXPECT_EQ(r.bank, BankId::D1);
  EXPECT_EQ(r.offset, 0x21);
  EXPECT_FALSE(r.bit);
  EXPECT_EQ(ref("D1.oil_temperature", SourceUse::analog), r);
  EXPECT_EQ(ref("D1+33", SourceUse::analog).offset, 33);
  EXPECT_EQ(ref("S1+0x00", SourceUse::analog).bank, BankId::S1);
  EXPECT_EQ(ref("W+0x03", SourceUse::analog).offset, 3);
  EXPECT_EQ(ref("C+0x00", SourceUse::analog).bank, BankId::C);
  r = ref("D1+0x15.3", SourceUse::bit);
  EXPECT_EQ(r.offset, 0x15);
  EXPECT_EQ(r.bit, 3);
  r = ref("X.0", SourceUse::bit);
  EXPECT_EQ(r.bank, BankId::X);
  EXPECT_EQ(r.offset, 0);
  EXPECT_EQ(r.bit, 0);
  r = ref("D1.status.11", SourceUse::bit);
  EXPECT_EQ(r.offset, 0);
  EXPECT_EQ(r.bit, 11);
}

TEST(SourceRef, SingleBitFieldsByName) {
  const auto* chp = banks::find_device_type("unigen-chp");
  ASSERT_NE(chp, nullptr);
  const auto field = chp->find_bit("power_mode");
  ASSERT_TRUE(field);
  const auto r = ref("D1.power_mode", SourceUse::bit);
  EXPECT_EQ(r.offset, field->offset);
  EXPECT_EQ(r.bit, field->bit);
}

TEST(SourceRef, ErrorsSayWhatIsWrong) {
  EXPECT_EQ(ref_error("Q1+0x00", SourceUse::analog), "'Q1+0x00': unknown bank 'Q1'");
  EXPECT_EQ(ref_error("D1+0x40", SourceUse::analog), "'D1+0x40': offset 0x40 is past the end of bank D1 (64 registers)");
  // A USC's D_N is 64 registers (seed §6.1), but past its table of 40 there is nothing to read.
  EXPECT_EQ(ref_error("D3+0x28", SourceUse::analog),
            "'D3+0x28': offset 0x28 is past the end of the usc table of bank D3 (40 registers): it always reads 0x7FFF");
  EXPECT_EQ(ref_error("D3+0x40", SourceUse::analog), "'D3+0x40': offset 0x40 is past the end of bank D3 (64 registers)");
  EXPECT_EQ(ref_error("D1.no_such", SourceUse::analog),
            "'D1.no_such': D1 (unigen-chp) has no register or single-bit field named 'no_such'");
  EXPECT_EQ(ref_error("D1+0x15", SourceUse::bit), "'D1+0x15' names a whole register; a bit source needs a bit, e.g. D1+0x15.0");
  EXPECT_EQ(ref_error("D1+0x15.3", SourceUse::analog), "'D1+0x15.3' is a bit; an analog register needs a whole register");
  EXPECT_EQ(ref_error("D1+0x15.16", SourceUse::bit), "'D1+0x15.16': bit '16' is not 0..15");
  EXPECT_EQ(ref_error("A+0x00", SourceUse::analog), "'A+0x00': bank A cannot be a source of bank A");
  EXPECT_EQ(ref_error("B.0", SourceUse::bit), "'B.0': mapped bits (B, C+0x10, C+0x12) cannot be the source of mapped bits");
  EXPECT_EQ(ref_error("C+0x10", SourceUse::analog),
            "'C+0x10': mapped bits (B, C+0x10, C+0x12) cannot be a source of bank A, whose bits they may show");
  EXPECT_EQ(ref_error("W.some_name", SourceUse::analog), "'W.some_name': bank W has no named registers; write W+0x00");
  EXPECT_EQ(ref_error("+0x00", SourceUse::analog), "'+0x00' is not a source (write e.g. D1+0x21, D1.oil_temperature)");
  EXPECT_NE(ref_error("D1", SourceUse::analog).find("is not a source"), std::string::npos);
  auto parsed = config::parse_source_ref("D1+0x00", config::bank_shapes(load("{}")), SourceUse::analog);
  ASSERT_TRUE(std::holds_alternative<std::string>(parsed));
  EXPECT_EQ(std::get<std::string>(parsed), "'D1+0x00': bank D1 has no device configured (devices.D1)");
}

// A register space of a config, with D1 on-line.
class Mapped : public ::testing::Test {
 protected:
  void SetUp() override {
    config = load(devices_yaml +
                  "mapping:\n"
                  "  A: [ D1.oil_temperature, ~, W+0x02, S1+0x00 ]\n"
                  "  B: [ D1+0x11.7, X.3, ~, S1+0x10.0 ]\n"
                  "  user_inputs: [ D1+0x11.0 ]\n"
                  "  user_outputs: [ ~, X.1 ]\n"
                  "blocks:\n"
                  "  - { type: read, register: 0x0200, source: D1+0x01 }\n"
                  "  - { type: write, register: 0x0201, output: 4 }\n");
    store = std::make_unique<banks::RegisterStore>(config::bank_shapes(config));
    store->set_mapping(config.mapping);
    space = std::make_unique<banks::RegisterSpace>(config::address_map(config), *store, banks::AccessRules{});
    writes = std::make_unique<banks::WritePath>(*space, nullptr);
    store->set_online(BankId::D1, true);
  }
  std::uint16_t read(std::uint16_t address) {
    std::uint16_t value = 0;
    EXPECT_TRUE(space->read(address, std::span(&value, 1))) << std::hex << address;
    return value;
  }
  void telegram(BankId bank, std::uint16_t offset, std::uint16_t value) {
    store->store_telegram(bank, offset, std::span(&value, 1));
  }
  config::Config config;
  std::unique_ptr<banks::RegisterStore> store;
  std::unique_ptr<banks::RegisterSpace> space;
  std::unique_ptr<banks::WritePath> writes;
  bool write(std::uint16_t address, std::uint16_t value) {
    return writes->write_registers(address, std::span(&value, 1), nullptr).status == modbus::WriteResult::Status::written;
  }
};

TEST_F(Mapped, BankAFollowsItsSourcesAtOnce) {
  EXPECT_EQ(read(0x1000), 0x7FFF);  // source never carried
  telegram(BankId::D1, 0x21, 853);
  EXPECT_EQ(read(0x1000), 853);
  telegram(BankId::D1, 0x21, 854);
  EXPECT_EQ(read(0x1000), 854);
  EXPECT_EQ(read(0x1001), 0x7FFF);  // unmapped entry
  std::uint16_t w = 1234;
  ASSERT_TRUE(write(0x3002, w));
  EXPECT_EQ(read(0x1002), 1234);
  EXPECT_EQ(read(0x1003), 0x7FFF);  // S1 off-line
  EXPECT_EQ(read(0x100F), 0x7FFF);
  store->set_online(BankId::D1, false);
  EXPECT_EQ(read(0x1000), 0x7FFF);  // source device off-line
}

// SPEC §1: A shows a quantity in 0.1 of its unit; 0x7FFF while its source is off-line or
// not measured, whatever the source's kind.
TEST(BankA, ConvertsToTenthsAndReadsNotMeasuredForEveryKindOfSourceOffLine) {
  const auto config = load(
      "devices:\n"
      "  D1: { type: unigen-chp, address: 5 }\n"
      "  D2: { type: uis, address: 5 }\n"
      "  D3: { type: nsu2, address: 5 }\n"
      "mapping:\n"
      "  A: [ D1.engine_speed, D1.oil_temperature, { source: D1.engine_speed, raw: true }, D1+0x00,\n"
      "       D1.operating_hours_low, D1.operating_hours_high, D2+0x28, D3+0x28, W+0x00 ]\n");
  banks::RegisterStore store(config::bank_shapes(config));
  store.set_mapping(config.mapping);
  // Off-line (never heard): every entry, of every kind, reads "not measured".
  for (std::uint16_t entry = 0; entry < 9; ++entry) EXPECT_EQ(store.read(BankId::A, entry), 0x7FFF) << entry;

  store.set_online(BankId::D1, true);
  store.set_online(BankId::D2, true);
  store.set_online(BankId::D3, true);
  const std::uint16_t d1[] = {0x0081, 1500, 0x1234, 0x0002};
  store.store_telegram(BankId::D1, 0x00, d1);
  const std::uint16_t oil = static_cast<std::uint16_t>(-53);  // -5.3 °C
  store.store_telegram(BankId::D1, 0x21, std::span(&oil, 1));
  const std::uint16_t firing = 0x6480;
  store.store_telegram(BankId::D2, 0x28, std::span(&firing, 1));
  EXPECT_EQ(store.read(BankId::A, 0), 15000);  // 1500 min⁻¹ in 0.1 min⁻¹
  EXPECT_EQ(store.read(BankId::A, 1), oil);     // 0.1 °C already, sign kept
  EXPECT_EQ(store.read(BankId::A, 2), 1500);    // raw: true
  EXPECT_EQ(store.read(BankId::A, 3), 0x0081);  // a bit word is copied
  EXPECT_EQ(store.read(BankId::A, 4), 0x1234);  // so are the halves of a 32-bit value
  EXPECT_EQ(store.read(BankId::A, 5), 0x0002);
  EXPECT_EQ(store.read(BankId::A, 6), 0x6480);  // and byte pairs
  EXPECT_EQ(store.read(BankId::A, 7), 0x7FFF);  // on-line, but the ASCII pair never carried
  EXPECT_EQ(store.read(BankId::A, 8), 0x7FFF);  // W+0x00 never written

  store.set_online(BankId::D1, false);
  store.set_online(BankId::D2, false);
  for (std::uint16_t entry = 0; entry < 7; ++entry) EXPECT_EQ(store.read(BankId::A, entry), 0x7FFF) << entry;
}

TEST(BankA, TheMapShowsTheUnitBankAHoldsItIn) {
  const auto config = load(
      "devices: { D1: { type: unigen-chp, address: 5 } }\n"
      "mapping:\n"
      "  A: [ D1.engine_speed, { source: D1.engine_speed, raw: true }, D1+0x00 ]\n");
  const auto rows = config::register_map(config);
  std::vector<config::MapRow> a;
  for (const auto& row : rows)
    if (row.bank == "A") a.push_back(row);
  ASSERT_EQ(a.size(), 16u);
  EXPECT_EQ(a[0].unit, "min-1");
  EXPECT_DOUBLE_EQ(a[0].scale, 0.1);
  EXPECT_DOUBLE_EQ(a[1].scale, 1.0);
  EXPECT_EQ(a[1].source, "D1.engine_speed (raw)");
  EXPECT_EQ(a[2].kind, "bits");
}

TEST_F(Mapped, BankBAndUserBitsComposeTheirSourceBits) {
  EXPECT_EQ(read(0x1010), 0);
  telegram(BankId::D1, 0x11, 0x0081);  // bits 0 and 7
  EXPECT_EQ(read(0x1010), 0x0001);
  std::uint16_t x = 0x000A;  // bits 1 and 3
  ASSERT_TRUE(write(0x3010, x));
  EXPECT_EQ(read(0x1010), 0x0003);
  EXPECT_EQ(read(0x1020 + 0x10), 0x0001);  // user inputs bit 0 = D1+0x11.0
  EXPECT_EQ(read(0x1020 + 0x12), 0x0002);  // user outputs bit 1 = X.1
  store->set_online(BankId::D1, false);
  EXPECT_EQ(read(0x1010), 0x0002);  // an off-line source's bits read 0
  EXPECT_EQ(read(0x1020 + 0x10), 0);
}

TEST_F(Mapped, UserBitsArePublishedWhenTheirSourcesChange) {
  std::vector<std::tuple<BankId, std::uint16_t, std::uint16_t>> published;
  store->set_change_listener([&](BankId b, std::uint16_t o, std::uint16_t v) { published.emplace_back(b, o, v); });
  telegram(BankId::D1, 0x11, 0x0001);  // user_inputs bit 0
  telegram(BankId::D1, 0x11, 0x0003);  // no change of bit 0: nothing more
  std::uint16_t x = 0x0002;            // user_outputs bit 1 = X.1
  ASSERT_TRUE(write(0x3010, x));
  store->set_online(BankId::D1, false);  // its bits read 0 now
  const std::vector<std::tuple<BankId, std::uint16_t, std::uint16_t>> expected = {
      {BankId::C, 0x10, 0x0001}, {BankId::X, 0, 0x0002}, {BankId::C, 0x12, 0x0002}, {BankId::C, 0x10, 0x0000}};
  EXPECT_EQ(published, expected);
}

TEST_F(Mapped, ReadBlockReadsItsSource) {
  EXPECT_EQ(read(0x0200), 0x7FFF);
  telegram(BankId::D1, 0x01, 1500);
  EXPECT_EQ(read(0x0200), 1500);
}

TEST_F(Mapped, WriteBlockSetsItsUserOutputAndPublishes) {
  std::vector<std::tuple<BankId, std::uint16_t, std::uint16_t>> published;
  store->set_change_listener([&](BankId b, std::uint16_t o, std::uint16_t v) { published.emplace_back(b, o, v); });
  std::uint16_t value = 2345;
  ASSERT_TRUE(write(0x0201, value));
  EXPECT_EQ(read(0x1020 + 3), 2345);  // UsrAO 4 = C+0x03
  ASSERT_EQ(published.size(), 1u);
  EXPECT_EQ(published[0], std::make_tuple(BankId::C, std::uint16_t{3}, std::uint16_t{2345}));
  std::uint16_t out = 0;
  EXPECT_FALSE(space->read(0x0201, std::span(&out, 1)));  // RegW is write-only
  EXPECT_FALSE(write(0x0200, value));  // RegR is read-only
}

std::string config_error(const std::string& yaml) {
  return test_support::error_message<config::ConfigError>([&] { (void)load(yaml); }, "(accepted)");
}

TEST(BlocksConfig, ABlockRegisterInsideABankIsRejectedNamingBoth) {
  EXPECT_EQ(config_error(devices_yaml + "blocks:\n  - { type: read, register: 0x1005, source: D1+0x01 }\n"),
            "t.yaml:7:5: bank A (0x1000..0x100F) overlaps read block 0x1005 (0x1005..0x1005)");
  EXPECT_EQ(config_error(devices_yaml +
                         "blocks:\n  - { type: read, register: 0x0200, source: D1+0x01 }\n"
                         "  - { type: write, register: 0x0200, output: 1 }\n"),
            "t.yaml:8:5: read block 0x0200 (0x0200..0x0200) overlaps write block 0x0200 (0x0200..0x0200)");
}

TEST(BlocksConfig, OutputsAreNotShared) {
  EXPECT_EQ(config_error("blocks:\n  - { type: write, register: 0x0201, output: 1 }\n"
                         "  - { type: capture, device: 3, register: 0x0202, output: 1 }\n"),
            "t.yaml:3:59: user analog output 1 is already the output of the block at t.yaml:2:5");
  EXPECT_EQ(config_error("blocks:\n  - { type: write, register: 0x0201, output: 17 }\n"),
            "t.yaml:2:46: 17 is out of range 1..16");
}

TEST(BlocksConfig, CaptureOfTheOwnAddressIsRejected) {
  EXPECT_EQ(config_error("modbus: { address: 3 }\nblocks:\n  - { type: capture, device: 3, register: 0x0202, output: 2 }\n"),
            "t.yaml:3:30: a capture block listens to another device; 3 is the bridge's own Modbus address "
            "(modbus.address)");
}

TEST(BlocksConfig, MissingAndUnknownKeys) {
  EXPECT_EQ(config_error("blocks:\n  - { type: read, register: 0x0200 }\n"), "t.yaml:2:5: a read block needs 'source'");
  EXPECT_EQ(config_error("blocks:\n  - { type: write, register: 0x0201, output: 1, period: 1s }\n"),
            "t.yaml:2:49: unknown key 'period' in a write block (known: type, register, output)");
  EXPECT_EQ(config_error("blocks:\n  - { type: jump, register: 1 }\n"),
            "t.yaml:2:13: 'jump' is not one of: read, write, capture, poll, send");
  EXPECT_EQ(config_error("blocks:\n  - { type: poll, device: 1, register: 0x0200, period: 0s, output: 3 }\n"),
            "t.yaml:2:56: the period must be longer than 0");
}

TEST(BlocksConfig, MasterBlocksAreIgnoredInSlaveModeWithAWarning) {
  const auto c = load("blocks:\n  - { type: poll, device: 1, register: 0x0200, period: 1s, output: 3 }\n"
                      "  - { type: send, device: 1, register: 0x0201, period: 2s, source: W+0x00 }\n"
                      "  - { type: write, register: 0x0201, output: 1 }\n");
  ASSERT_EQ(c.blocks.size(), 3u);
  EXPECT_EQ(c.active_blocks().size(), 1u);
  const auto w = config::warnings(c);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(w[0], "t.yaml:2:5: warning: poll block ignored: poll blocks act in master mode only, this bridge is a slave");
  // The send block's register 0x0201 does not collide with the write block: it is not served.
  EXPECT_NE(config::address_map(c).find(0x0201), nullptr);
}

TEST(MappingConfig, ErrorsPointAtTheEntry) {
  EXPECT_EQ(config_error(devices_yaml + "mapping:\n  A: [ D1+0x21, D9+0x00 ]\n"), "t.yaml:7:17: 'D9+0x00': unknown bank 'D9'");
  EXPECT_EQ(config_error("mapping:\n  B: [ X+0x00 ]\n"),
            "t.yaml:2:8: 'X+0x00' names a whole register; a bit source needs a bit, e.g. X+0x00.0");
  EXPECT_EQ(config_error("mapping:\n  C: []\n"),
            "t.yaml:2:3: unknown key 'C' in mapping (known: A, B, user_inputs, user_outputs)");
  std::string many = "mapping:\n  A: [";
  for (int i = 0; i < 17; ++i) many += "W+0x00, ";
  many += "]\n";
  EXPECT_EQ(config_error(many), "t.yaml:2:6: mapping.A has 17 entries; there are 16");
}

// Found with the config loader's fuzz target (docs/fuzzing.md): `check` accepted this,
// and the daemon's start (publishing the user bits) or a read of A or C+0x10 recursed
// until the stack overflowed.
TEST(MappingConfig, AMappingThatReadsItselfIsRefused) {
  EXPECT_EQ(config_error("mapping:\n  A: [ C+0x10 ]\n  user_inputs: [ A+0x00.0 ]\n"),
            "t.yaml:2:8: 'C+0x10': mapped bits (B, C+0x10, C+0x12) cannot be a source of bank A, whose bits they may "
            "show");
  EXPECT_NE(config_error("mapping:\n  A: [ B+0x00 ]\n  B: [ A+0x00.0 ]\n"), "(no error)");
}

TEST(RegisterMap, ListsEveryRegisterOfTheConfiguredTables) {
  const auto c = load(devices_yaml);
  const auto rows = config::register_map(c);
  for (unsigned n = 1; n <= 4; ++n) {
    const auto bank = banks::device_bank(n);
    const auto* table = c.devices[n - 1]->table;
    for (const auto& reg : table->registers) {
      const auto address = static_cast<std::uint16_t>(banks::default_base(bank) + reg.offset);
      const auto row = std::find_if(rows.begin(), rows.end(), [&](const auto& r) { return r.address == address; });
      ASSERT_NE(row, rows.end()) << banks::bank_name(bank) << " " << reg.id;
      EXPECT_EQ(row->id, reg.id);
      EXPECT_EQ(row->bank, banks::bank_name(bank));
      EXPECT_EQ(row->label, reg.label);
      EXPECT_EQ(row->unit, reg.unit);
    }
  }
  const auto oil = std::find_if(rows.begin(), rows.end(), [](const auto& r) { return r.address == 0x1121; });
  ASSERT_NE(oil, rows.end());
  EXPECT_EQ(oil->id, "oil_temperature");
  EXPECT_EQ(oil->unit, "°C");
  EXPECT_DOUBLE_EQ(oil->scale, 0.1);
  EXPECT_EQ(oil->access, "R");
  // The USC's table ends at +0x27; its D_N goes on to +0x3F (seed §6.1), as reserves.
  for (std::uint16_t address = 0x1328; address <= 0x133F; ++address) {
    const auto row = std::find_if(rows.begin(), rows.end(), [&](const auto& r) { return r.address == address; });
    ASSERT_NE(row, rows.end()) << address;
    EXPECT_EQ(row->bank, "D3");
    EXPECT_EQ(row->kind, "reserve");
    EXPECT_EQ(row->id, fmt::format("reserve_{:02x}", address - 0x1300));
    EXPECT_EQ(row->access, "R");
  }
  EXPECT_TRUE(std::none_of(rows.begin(), rows.end(), [](const auto& r) { return r.address == 0x1340; }));
  EXPECT_TRUE(std::is_sorted(rows.begin(), rows.end(), [](const auto& a, const auto& b) { return a.address < b.address; }));
}

TEST(RegisterReference, DocsRegistersMdIsUpToDate) {
  std::ifstream in(UNIMA_SOURCE_DIR "/docs/registers.md");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_TRUE(text.str() == banks::tables_markdown())
      << "docs/registers.md is out of date: run `build/bin/unima-bridge tables > docs/registers.md`";
}

TEST(RegisterReference, EveryIdentifierOfTheDataIsInTheDocs) {
  const auto docs = banks::tables_markdown();
  for (const auto* table : banks::all_tables())
    for (const auto& reg : table->registers) {
      EXPECT_NE(docs.find("`" + reg.id + "`"), std::string::npos) << table->id << " " << reg.id;
      for (const auto& field : reg.fields) EXPECT_NE(docs.find("`" + field.id + "`"), std::string::npos) << field.id;
    }
}

// Offsets and bits the PDF text lost or garbled, inferred from the sibling tables (SPEC §2).
// Each stays where it was inferred and says so in the data; a new inference must be added
// here on purpose.
TEST(InferredOffsets, AreExactlyTheReviewedOnesAndEachSaysWhy) {
  const std::set<std::tuple<std::string, std::uint16_t, std::string>> expected = {
      {"bridge-tem", 0x2B, "reserve_2b"},          {"bridge-tem", 0x2C, "reserve_2c"},
      {"bridge-tem", 0x2D, "reserve_2d"},          {"bridge-tem", 0x2E, "reserve_2e"},
      {"microgen-sync", 0x00, "status"},           {"microgen-sync", 0x16, "reserve_16"},
      {"microgen-sync", 0x17, "mode_outputs"},     {"nsu2", 0x14, "user_binary_outputs_1_16"},
      {"nsu2", 0x15, "state_outputs"},             {"nsu2", 0x16, "mains_generator_protections"},
      {"nsu2", 0x20, "user_analog_output_9"},      {"nsu2", 0x21, "user_analog_output_10"},
      {"nsu2", 0x22, "user_analog_output_11"},     {"nsu2", 0x23, "user_analog_output_12"},
      {"nsu2", 0x24, "user_analog_output_13"},     {"nsu2", 0x25, "user_analog_output_14"},
      {"nsu2", 0x26, "user_analog_output_15"},     {"nsu2", 0x27, "user_analog_output_16"},
      {"uis", 0x10, "user_binary_inputs_1_16"},    {"uis", 0x11, "control_inputs"},
      {"unigen-chp", 0x00, "status"},              {"unigen-chp", 0x13, "user_binary_inputs_17_28"},
      {"unigen-chp", 0x18, "user_analog_output_1"}, {"unigen-mve", 0x00, "status"},
      {"unigen-tem", 0x00, "status"},              {"usc", 0x11, "control_inputs"},
      {"uvr", 0x11, "control_inputs"},
  };
  std::set<std::tuple<std::string, std::uint16_t, std::string>> found;
  for (const auto* table : banks::all_tables())
    for (const auto& reg : table->registers) {
      bool noted = reg.inferred.size() > 20;
      for (const auto& f : reg.fields) noted = noted || f.inferred.size() > 20;
      if (noted) found.emplace(table->id, reg.offset, reg.id);
    }
  EXPECT_EQ(found, expected);
}

TEST(InferredOffsets, TheSpecExamples) {
  // SPEC §2 names NSU2 +0x14..+0x16, MicroGEN-SYNC +0x16/+0x17 and UniGEN-CHP +0x13 bit 0.
  const auto* chp = banks::find_device_type("unigen-chp");
  ASSERT_NE(chp, nullptr);
  const auto& r13 = chp->registers[0x13];
  ASSERT_FALSE(r13.fields.empty());
  EXPECT_EQ(r13.fields[0].first_bit, 0);
  EXPECT_FALSE(r13.fields[0].inferred.empty());
  EXPECT_EQ(banks::find_device_type("nsu2")->registers[0x16].kind, banks::RegisterKind::bits);
  EXPECT_EQ(banks::find_device_type("microgen-sync")->registers[0x17].kind, banks::RegisterKind::bits);
}

}  // namespace
}  // namespace unima
