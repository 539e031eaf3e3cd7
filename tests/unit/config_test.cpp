// The YAML configuration (SPEC §7): values, defaults, and errors that name the file, the
// 1-based line and the 1-based column of the offending node.

#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "banks/table_catalog.hpp"
#include "config/config.hpp"
#include "config/yaml_reader.hpp"
#include "tests/support/error_message.hpp"

namespace unima::config {
namespace {

using namespace std::chrono_literals;
using banks::BankId;

bool starts_with(const std::string& text, const std::string& prefix) { return text.rfind(prefix, 0) == 0; }
bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// The message of the ConfigError that loading `text` throws, or "(no error)".
std::string load_error(const std::string& text, const std::string& origin = "cfg.yaml") {
  return test_support::error_message<ConfigError>([&] { (void)load_text(text, origin); });
}

// The example of SPEC §7, with the sections this version has: unimabus, modbus (tcp),
// banks, devices, log.
constexpr const char* spec_example =
    "unimabus:\n"
    "  address: 5                 # the bridge's own UnimaBUS address (\"Addr\")\n"
    "  transport: feed            # sim | feed | replay\n"
    "  listen: 127.0.0.1:7700     # feed only\n"
    "  offline_after: 5s\n"
    "modbus:\n"
    "  mode: slave                # slave | master\n"
    "  address: 1                 # \"MBSAddr\"\n"
    "  tcp: { listen: 127.0.0.1, port: 5020 }\n"
    "banks: { A: 0x1000, B: 0x1010, C: 0x1020, D1: 0x1100, S1: 0x2100, W: 0x3000, X: 0x3010 }\n"
    "devices:\n"
    "  D1: { type: unigen-chp, address: 5 }\n"
    "log:\n"
    "  level: debug\n";

TEST(ConfigLoad, SpecExample) {
  const Config c = load_text(spec_example, "bridge.yaml");
  EXPECT_EQ(c.file, "bridge.yaml");
  EXPECT_EQ(c.unimabus.address, 5);
  EXPECT_EQ(c.unimabus.transport, TransportKind::feed);
  EXPECT_EQ(c.unimabus.listen, "127.0.0.1:7700");
  EXPECT_EQ(c.unimabus.offline_after, 5s);
  EXPECT_EQ(c.modbus.mode, ModbusMode::slave);
  EXPECT_EQ(c.modbus.address, 1);
  ASSERT_TRUE(c.modbus.tcp.has_value());
  EXPECT_EQ(c.modbus.tcp->listen, "127.0.0.1");
  EXPECT_EQ(c.modbus.tcp->port, 5020);
  EXPECT_EQ(c.modbus.tcp->max_clients, 128u);
  EXPECT_TRUE(c.modbus.readable_write_banks);
  EXPECT_EQ(c.bank_bases[index_of(BankId::A)], 0x1000);
  EXPECT_EQ(c.bank_bases[index_of(BankId::D1)], 0x1100);
  EXPECT_EQ(c.bank_bases[index_of(BankId::S1)], 0x2100);
  EXPECT_EQ(c.bank_bases[index_of(BankId::W)], 0x3000);
  EXPECT_EQ(c.bank_bases[index_of(BankId::X)], 0x3010);
  EXPECT_EQ(c.bank_bases[index_of(BankId::S2)], 0x2200);  // not in the file: default
  // Banks set in the file remember where (line 10); the others do not.
  EXPECT_EQ(c.bank_origins[index_of(BankId::A)], "bridge.yaml:10:13");
  EXPECT_TRUE(starts_with(c.bank_origins[index_of(BankId::X)], "bridge.yaml:10:")) << c.bank_origins[index_of(BankId::X)];
  EXPECT_TRUE(c.bank_origins[index_of(BankId::S2)].empty());
  ASSERT_TRUE(c.devices[0].has_value());
  EXPECT_EQ(c.devices[0]->table, banks::find_device_type("unigen-chp"));
  EXPECT_EQ(c.devices[0]->address, 5);
  EXPECT_FALSE(c.devices[1].has_value());
  EXPECT_FALSE(c.devices[2].has_value());
  EXPECT_FALSE(c.devices[3].has_value());
  EXPECT_EQ(c.log.level, "debug");
}

TEST(ConfigLoad, ShapesAndAddressMapOfTheSpecExample) {
  const Config c = load_text(spec_example, "bridge.yaml");
  const auto shapes = bank_shapes(c);
  EXPECT_EQ(shapes[index_of(BankId::D1)].length, 64);
  EXPECT_EQ(shapes[index_of(BankId::D1)].table, banks::find_device_type("unigen-chp"));
  EXPECT_EQ(shapes[index_of(BankId::D2)].length, 0);
  EXPECT_EQ(shapes[index_of(BankId::A)].length, 16);
  EXPECT_EQ(shapes[index_of(BankId::C)].length, 20);
  EXPECT_EQ(shapes[index_of(BankId::S7)].length, 20);
  EXPECT_EQ(shapes[index_of(BankId::W)].length, 16);
  EXPECT_EQ(shapes[index_of(BankId::X)].length, 1);

  const auto map = address_map(c);
  EXPECT_EQ(map.windows().size(), 13u);  // A B C D1 S1..S7 W X
  struct Probe {
    std::uint16_t address;
    BankId bank;
  };
  for (const auto& p : {Probe{0x1000, BankId::A}, Probe{0x1010, BankId::B}, Probe{0x1033, BankId::C},
                        Probe{0x1100, BankId::D1}, Probe{0x113F, BankId::D1}, Probe{0x2100, BankId::S1},
                        Probe{0x2713, BankId::S7}, Probe{0x300F, BankId::W}, Probe{0x3010, BankId::X}}) {
    const auto* w = map.find(p.address);
    ASSERT_NE(w, nullptr) << std::hex << p.address;
    EXPECT_EQ(w->bank, p.bank) << std::hex << p.address;
  }
  EXPECT_EQ(map.find(0x1140), nullptr);
  EXPECT_EQ(map.find(0x1200), nullptr);  // no D2 device: no D2 bank
  EXPECT_EQ(map.find(0x2714), nullptr);
}

TEST(ConfigLoad, DefaultsWhenKeysAreMissing) {
  const Config c = load_text("modbus:\n  tcp: {}\n", "cfg.yaml");
  EXPECT_EQ(c.modbus.address, 1);
  EXPECT_EQ(c.modbus.mode, ModbusMode::slave);
  ASSERT_TRUE(c.modbus.tcp.has_value());
  EXPECT_EQ(c.modbus.tcp->port, 502);
  EXPECT_EQ(c.modbus.tcp->max_clients, 128u);
  EXPECT_EQ(c.modbus.tcp->listen, "0.0.0.0");
  EXPECT_TRUE(c.modbus.readable_write_banks);
  EXPECT_TRUE(c.modbus.extensions.function_3);
  EXPECT_TRUE(c.modbus.extensions.function_16);
  EXPECT_TRUE(c.modbus.extensions.function_43);
  EXPECT_EQ(c.unimabus.offline_after, 5s);
  EXPECT_EQ(c.unimabus.transport, TransportKind::sim);
  EXPECT_EQ(c.log.level, "info");
  for (BankId bank : banks::all_banks) {
    EXPECT_EQ(c.bank_bases[index_of(bank)], banks::default_base(bank)) << banks::bank_name(bank);
    EXPECT_TRUE(c.bank_origins[index_of(bank)].empty());
  }
}

TEST(ConfigLoad, EmptyFileIsAllDefaults) {
  const Config c = load_text("", "empty.yaml");
  EXPECT_EQ(c.modbus.address, 1);
  EXPECT_FALSE(c.modbus.tcp.has_value());
  EXPECT_EQ(c.unimabus.offline_after, 5s);
  for (const auto& d : c.devices) EXPECT_FALSE(d.has_value());
}

TEST(ConfigLoad, Durations) {
  struct Case {
    const char* text;
    Duration expected;
  };
  for (const auto& [text, expected] : {Case{"200ms", 200ms}, Case{"1s", 1s}, Case{"2s", 2s}, Case{"60s", 60s},
                                       Case{"5m", 5min}, Case{"1h", 1h}}) {
    const Config c = load_text(std::string("unimabus:\n  offline_after: ") + text + "\n", "cfg.yaml");
    EXPECT_EQ(c.unimabus.offline_after, expected) << text;
  }
  const Config c = load_text("modbus:\n  tcp: { idle_timeout: 90s }\n", "cfg.yaml");
  EXPECT_EQ(c.modbus.tcp->idle_timeout, 90s);
}

TEST(ConfigLoad, NumbersDecimalAndHex) {
  const Config c = load_text(
      "unimabus:\n"
      "  address: 0x10\n"
      "modbus:\n"
      "  address: 247\n"
      "  tcp: { port: 0x13BA }\n"
      "banks: { A: 4096, W: 0x4000, X: 0X4010 }\n",
      "cfg.yaml");
  EXPECT_EQ(c.unimabus.address, 16);
  EXPECT_EQ(c.modbus.address, 247);
  EXPECT_EQ(c.modbus.tcp->port, 5050);
  EXPECT_EQ(c.bank_bases[index_of(BankId::A)], 0x1000);
  EXPECT_EQ(c.bank_bases[index_of(BankId::W)], 0x4000);
  EXPECT_EQ(c.bank_bases[index_of(BankId::X)], 0x4010);
}

TEST(ConfigLoad, DeviceAliasesAndSeveralDevices) {
  const Config c = load_text(
      "devices:\n"
      "  D1: { type: microgen-chp, address: 5 }\n"
      "  D4: { type: usc, address: 0x20 }\n",
      "cfg.yaml");
  ASSERT_TRUE(c.devices[0] && c.devices[3]);
  EXPECT_EQ(c.devices[0]->table->id, "unigen-chp");
  EXPECT_EQ(c.devices[3]->table->id, "usc");
  EXPECT_EQ(c.devices[3]->address, 0x20);
  EXPECT_EQ(bank_shapes(c)[index_of(BankId::D4)].length, 64);  // the seed's window, whatever the type
  EXPECT_EQ(banks::filled_length(bank_shapes(c)[index_of(BankId::D4)]), 0x28);
}

TEST(ConfigLoad, FalseReadableWriteBanks) {
  const Config c = load_text("modbus:\n  readable_write_banks: false\n", "cfg.yaml");
  EXPECT_FALSE(c.modbus.readable_write_banks);
}

// ---------------------------------------------------------------------------------------
// Errors and their positions

TEST(ConfigErrors, UnknownTopLevelKey) {
  const auto m = load_error(
      "unimabus:\n"
      "  address: 5\n"
      "modbsu:\n"
      "  address: 1\n");
  EXPECT_TRUE(starts_with(m, "cfg.yaml:3:1: ")) << m;
  EXPECT_TRUE(contains(m, "modbsu")) << m;
}

TEST(ConfigErrors, UnknownKeyInModbusTcp) {
  const auto m = load_error(
      "modbus:\n"
      "  tcp:\n"
      "    port: 5020\n"
      "    backlog: 4\n");
  EXPECT_TRUE(starts_with(m, "cfg.yaml:4:5: ")) << m;
  EXPECT_TRUE(contains(m, "backlog")) << m;
}

TEST(ConfigErrors, AnAllowEntryThatIsNoRangeNamesItsPosition) {
  const auto m = load_error(
      "modbus:\n"
      "  tcp:\n"
      "    port: 5020\n"
      "    allow: [192.168.10.0/24, scada.plant]\n");
  EXPECT_TRUE(starts_with(m, "cfg.yaml:4:30: ")) << m;
  EXPECT_TRUE(contains(m, "modbus.tcp.allow: 'scada.plant' is not an IP address")) << m;
  EXPECT_TRUE(contains(load_error("modbus:\n  tcp: { allow: 10.0.0.0/8 }\n"), "must be a list")) << m;
}

TEST(Config, AllowAndReadOnlyOfTheTcpSlave) {
  const auto config = load_text("modbus:\n  tcp: { port: 5020, allow: [10.0.0.0/8, '::1'], read_only: true }\n", "cfg.yaml");
  ASSERT_TRUE(config.modbus.tcp);
  ASSERT_EQ(config.modbus.tcp->allow.ranges.size(), 2u);
  EXPECT_EQ(config.modbus.tcp->allow.ranges[0].text, "10.0.0.0/8");
  EXPECT_TRUE(config.modbus.tcp->read_only);
  const auto open = load_text("modbus:\n  tcp: { port: 5020 }\n", "cfg.yaml");
  EXPECT_TRUE(open.modbus.tcp->allow.empty());
  EXPECT_FALSE(open.modbus.tcp->read_only);
}

TEST(ConfigErrors, BadNumber) {
  const auto m = load_error(
      "modbus:\n"
      "  address: 12x\n");
  EXPECT_TRUE(starts_with(m, "cfg.yaml:2:12: ")) << m;
  EXPECT_TRUE(contains(m, "12x")) << m;
}

TEST(ConfigErrors, NumberOutOfRange) {
  const auto m = load_error(
      "unimabus:\n"
      "  address: 256\n");
  EXPECT_TRUE(starts_with(m, "cfg.yaml:2:12: ")) << m;
  EXPECT_TRUE(contains(m, "256")) << m;
}

TEST(ConfigErrors, HexOutOfRangeForABankBase) {
  const auto m = load_error(
      "banks:\n"
      "  W: 0x10000\n");
  EXPECT_TRUE(starts_with(m, "cfg.yaml:2:6: ")) << m;
  EXPECT_TRUE(contains(m, "0x10000")) << m;
}

TEST(ConfigErrors, BadDuration) {
  const auto m = load_error(
      "unimabus:\n"
      "  offline_after: 5 sec\n");
  EXPECT_TRUE(starts_with(m, "cfg.yaml:2:18: ")) << m;
  EXPECT_TRUE(contains(m, "5 sec")) << m;
  for (const char* bad : {"5", "ms", "-1s", "1.5s", "5S", "0x5s"}) {
    const auto e = load_error(std::string("unimabus:\n  offline_after: ") + bad + "\n");
    EXPECT_TRUE(starts_with(e, "cfg.yaml:2:18: ")) << bad << ": " << e;
  }
}

TEST(ConfigErrors, UnknownDeviceTypeListsTheKnownOnes) {
  const auto m = load_error(
      "devices:\n"
      "  D1: { type: unigen-xyz, address: 5 }\n");
  EXPECT_TRUE(starts_with(m, "cfg.yaml:2:15: ")) << m;
  EXPECT_TRUE(contains(m, "unigen-xyz")) << m;
  for (auto id : banks::device_type_ids()) EXPECT_TRUE(contains(m, std::string(id))) << id << ": " << m;
}

TEST(ConfigLoad, AUnitsComponentsShareItsAddress) {
  const Config c = load_text(
      "devices:\n"
      "  D1: { type: unigen-chp, address: 5 }\n"
      "  D2: { type: usc, address: 5 }\n"
      "  D3: { type: uvr, address: 5 }\n",
      "cfg.yaml");
  ASSERT_TRUE(c.devices[0] && c.devices[1] && c.devices[2]);
  EXPECT_EQ(c.devices[1]->table->id, "usc");
  EXPECT_EQ(c.devices[2]->address, 5);
}

TEST(ConfigErrors, TwoDevicesOfOneTypeAtOneAddressNameEachOther) {
  const auto m = load_error(
      "devices:\n"
      "  D1: { type: unigen-chp, address: 5 }\n"
      "  D3: { type: microgen-chp, address: 5 }\n");
  EXPECT_TRUE(starts_with(m, "cfg.yaml:3:7: ")) << m;
  EXPECT_TRUE(contains(m, "devices.D3 and devices.D1")) << m;
  EXPECT_TRUE(contains(m, "unigen-chp at UnimaBUS address 5")) << m;
}

TEST(ConfigErrors, ReplayKeysBelongToTheReplayTransport) {
  const auto stray = load_error(
      "unimabus:\n"
      "  transport: sim\n"
      "  speed: 2\n");
  EXPECT_TRUE(starts_with(stray, "cfg.yaml:3:10: ")) << stray;
  EXPECT_TRUE(contains(stray, "replay")) << stray;
  const auto no_file = load_error(
      "unimabus:\n"
      "  transport: replay\n");
  EXPECT_TRUE(starts_with(no_file, "cfg.yaml:2:3: ")) << no_file;
  EXPECT_TRUE(contains(no_file, "needs 'file'")) << no_file;
  const auto missing = load_error(
      "unimabus:\n"
      "  transport: replay\n"
      "  file: /nonexistent/recording.jsonl\n");
  EXPECT_TRUE(starts_with(missing, "cfg.yaml:3:9: cannot read the recording /nonexistent/recording.jsonl")) << missing;
  const auto record = load_error(
      "unimabus:\n"
      "  record: { max_files: 3 }\n");
  EXPECT_TRUE(starts_with(record, "cfg.yaml:2:11: ")) << record;
}

TEST(ConfigLoad, RecordKeys) {
  const Config c = load_text("unimabus:\n  record: { file: /var/lib/x/rec.jsonl, max_size: 1MB, max_files: 3 }\n", "cfg.yaml");
  EXPECT_EQ(c.unimabus.record.file, "/var/lib/x/rec.jsonl");
  EXPECT_EQ(c.unimabus.record.max_size, 1u << 20);
  EXPECT_EQ(c.unimabus.record.max_files, 3u);
  EXPECT_TRUE(load_text("", "cfg.yaml").unimabus.record.file.empty());
}

TEST(ConfigErrors, UnknownBankName) {
  const auto m = load_error(
      "banks:\n"
      "  A: 0x1000\n"
      "  D5: 0x4000\n");
  EXPECT_TRUE(starts_with(m, "cfg.yaml:3:3: ")) << m;
  EXPECT_TRUE(contains(m, "D5")) << m;
}

TEST(ConfigErrors, UnknownDeviceBank) {
  const auto m = load_error(
      "devices:\n"
      "  S1: { type: usc, address: 5 }\n");
  EXPECT_TRUE(starts_with(m, "cfg.yaml:2:3: ")) << m;
  EXPECT_TRUE(contains(m, "S1")) << m;
}

TEST(ConfigErrors, YamlSyntaxError) {
  // A second ':' in a plain value: reported at that colon.
  const auto m = load_error(
      "unimabus:\n"
      "  address: 5\n"
      "log:\n"
      "  level: info: x\n");
  EXPECT_TRUE(starts_with(m, "cfg.yaml:4:14: ")) << m;
  // A flow mapping closed with ']': reported at the bracket.
  const auto m2 = load_error(
      "unimabus:\n"
      "  address: 5\n"
      "modbus: { address: 1 ]\n");
  EXPECT_TRUE(starts_with(m2, "cfg.yaml:3:22: ")) << m2;
  // An unclosed flow sequence is found at the end of the text, the line after the last.
  const auto m3 = load_error(
      "unimabus:\n"
      "  address: 5\n"
      "modbus: [1, 2\n");
  EXPECT_TRUE(starts_with(m3, "cfg.yaml:4:1: ")) << m3;
}

TEST(ConfigErrors, FeedTransportWithoutListen) {
  const auto m = load_error(
      "unimabus:\n"
      "  transport: feed\n");
  EXPECT_TRUE(starts_with(m, "cfg.yaml:2:3: ")) << m;
  EXPECT_TRUE(contains(m, "listen")) << m;
}

TEST(ConfigErrors, FeedListenWithoutPort) {
  const auto m = load_error(
      "unimabus:\n"
      "  transport: feed\n"
      "  listen: 127.0.0.1\n");
  EXPECT_TRUE(starts_with(m, "cfg.yaml:3:11: ")) << m;
  EXPECT_NO_THROW(load_text("unimabus: { transport: feed, listen: \"unix:/run/feed.sock\" }\n", "cfg.yaml"));
}

TEST(ConfigErrors, ListenWithTheSimTransport) {
  const auto m = load_error(
      "unimabus:\n"
      "  transport: sim\n"
      "  listen: 127.0.0.1:7700\n");
  EXPECT_TRUE(starts_with(m, "cfg.yaml:3:11: ")) << m;
  EXPECT_TRUE(contains(m, "listen")) << m;
}

TEST(ConfigErrors, UnknownChoice) {
  const auto m = load_error(
      "log:\n"
      "  level: loud\n");
  EXPECT_TRUE(starts_with(m, "cfg.yaml:2:10: ")) << m;
  EXPECT_TRUE(contains(m, "loud")) << m;
  EXPECT_TRUE(contains(m, "info")) << m;
}

TEST(ConfigErrors, BanksOverlap) {
  const auto m = load_error(
      "banks: {D1: 0x0011, W: 0x0040}\n"
      "devices:\n"
      "  D1: { type: unigen-chp, address: 5 }\n");
  // The position of one of the two banks the file set: D1's value (1:13) or W's (1:24).
  EXPECT_TRUE(starts_with(m, "cfg.yaml:1:13: ") || starts_with(m, "cfg.yaml:1:24: ")) << m;
  EXPECT_TRUE(contains(m, "bank D1")) << m;
  EXPECT_TRUE(contains(m, "bank W")) << m;
  EXPECT_TRUE(contains(m, "0x0011")) << m;
  EXPECT_TRUE(contains(m, "0x0040")) << m;
}

TEST(ConfigErrors, BankOverlapsADefaultBank) {
  // Only W was set: the error points at it.
  const auto m = load_error(
      "banks:\n"
      "  W: 0x1130\n"
      "devices:\n"
      "  D1: { type: unigen-chp, address: 5 }\n");
  EXPECT_TRUE(starts_with(m, "cfg.yaml:2:6: ")) << m;
  EXPECT_TRUE(contains(m, "bank D1")) << m;
  EXPECT_TRUE(contains(m, "bank W")) << m;
}

TEST(ConfigErrors, BankPastTheLastAddress) {
  const auto m = load_error(
      "banks:\n"
      "  W: 0xFFF8\n");
  EXPECT_TRUE(starts_with(m, "cfg.yaml:2:6: ")) << m;
  EXPECT_TRUE(contains(m, "bank W")) << m;
}

TEST(ConfigErrors, BankWithoutDeviceDoesNotOverlap) {
  // D2 has no device, so it has no window and cannot overlap W.
  EXPECT_NO_THROW(load_text("banks: { D2: 0x3000 }\n", "cfg.yaml"));
}

TEST(ConfigErrors, ConfigIsNotAMapping) {
  const auto m = load_error("- a\n- b\n");
  EXPECT_TRUE(starts_with(m, "cfg.yaml:1:1: ")) << m;
}

TEST(ConfigFile, LoadFileOfAMissingFileNamesThePath) {
  const std::string path = ::testing::TempDir() + "no-such-dir-unima/bridge.yaml";
  try {
    (void)load_file(path);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    const std::string m = e.what();
    EXPECT_TRUE(starts_with(m, path)) << m;
  }
}

TEST(ConfigFile, LoadFileUsesThePathAsOrigin) {
  const std::string path = ::testing::TempDir() + "unima_config_test_bridge.yaml";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << "modbus:\n  address: 7\n";
  }
  const Config c = load_file(path);
  EXPECT_EQ(c.modbus.address, 7);
  EXPECT_EQ(c.file, path);
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << "modbus:\n  address: 7\n  colour: red\n";
  }
  try {
    (void)load_file(path);
    ADD_FAILURE() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_TRUE(starts_with(e.what(), path + ":3:3: ")) << e.what();
  }
  std::remove(path.c_str());
}

// ---------------------------------------------------------------------------------------
// YamlReader on its own

std::string reader_error(const std::function<void(const YamlReader&, const YAML::Node&)>& use, const std::string& text) {
  const YamlReader reader("r.yaml");
  const YAML::Node root = YAML::Load(text);
  try {
    use(reader, root);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(YamlReader, Numbers) {
  const YamlReader r("r.yaml");
  const YAML::Node n = YAML::Load("{ a: 10, b: 0x1F, c: 0XFF, d: 0, e: 4294967295 }");
  EXPECT_EQ(r.number(n["a"], 0, 100), 10u);
  EXPECT_EQ(r.number(n["b"], 0, 100), 31u);
  EXPECT_EQ(r.number(n["c"], 0, 255), 255u);
  EXPECT_EQ(r.number(n["d"], 0, 1), 0u);
  EXPECT_EQ(r.number(n["e"], 0, 0xFFFFFFFF), 0xFFFFFFFFu);
  for (const char* bad : {"x: 12x", "x: -1", "x: 0x", "x: ''", "x: 1.5", "x: 0xG", "x: [1]", "x: +5", "x: ' 5'"}) {
    const auto m = reader_error([](const YamlReader& rd, const YAML::Node& root) { (void)rd.number(root["x"], 0, 100); }, bad);
    EXPECT_TRUE(starts_with(m, "r.yaml:1:4: ")) << bad << ": " << m;
  }
  const auto m = reader_error([](const YamlReader& rd, const YAML::Node& root) { (void)rd.number(root["x"], 1, 7); }, "x: 0");
  EXPECT_TRUE(starts_with(m, "r.yaml:1:4: ")) << m;
}

TEST(YamlReader, BooleansAndChoices) {
  const YamlReader r("r.yaml");
  const YAML::Node n = YAML::Load("{ t: true, f: false, y: yes, o: off, bad: maybe, lvl: warn }");
  EXPECT_TRUE(r.boolean(n["t"]));
  EXPECT_FALSE(r.boolean(n["f"]));
  EXPECT_TRUE(r.boolean(n["y"]));
  EXPECT_FALSE(r.boolean(n["o"]));
  EXPECT_THROW(r.boolean(n["bad"]), ConfigError);
  EXPECT_EQ(r.choice(n["lvl"], {"info", "warn"}), "warn");
  try {
    (void)r.choice(n["bad"], {"info", "warn"});
    ADD_FAILURE() << "expected ConfigError";
  } catch (const ConfigError& e) {
    const std::string m = e.what();
    EXPECT_TRUE(contains(m, "info") && contains(m, "warn") && contains(m, "maybe")) << m;
  }
}

TEST(YamlReader, Durations) {
  const YamlReader r("r.yaml");
  const YAML::Node n = YAML::Load("{ a: 200ms, b: 1s, c: 5m, d: 1h, e: 0s }");
  EXPECT_EQ(r.duration(n["a"]), 200ms);
  EXPECT_EQ(r.duration(n["b"]), 1000ms);
  EXPECT_EQ(r.duration(n["c"]), 300000ms);
  EXPECT_EQ(r.duration(n["d"]), 3600000ms);
  EXPECT_EQ(r.duration(n["e"]), 0ms);
}

TEST(YamlReader, ExpectKeysAndPositions) {
  const YamlReader r("r.yaml");
  EXPECT_NO_THROW(r.expect_keys(YAML::Node(), "empty", {"a"}));  // null counts as an empty mapping
  const auto m = reader_error(
      [](const YamlReader& rd, const YAML::Node& root) { rd.expect_keys(root["sec"], "sec", {"alpha", "beta"}); },
      "sec:\n  alpha: 1\n  gamma: 2\n");
  EXPECT_TRUE(starts_with(m, "r.yaml:3:3: ")) << m;
  EXPECT_TRUE(contains(m, "gamma") && contains(m, "alpha") && contains(m, "beta")) << m;
  const YAML::Node n = YAML::Load("a:\n  b: 1\n");
  EXPECT_EQ(r.position(n["a"]["b"]), "r.yaml:2:6");
}

// http (SPEC §13): HTTPS and users, and what a bridge open beyond loopback is warned of.
// Issue 44, finding 2: the users written in the config instead of a file's path.
TEST(ConfigErrors, HttpUsersWrittenInPlaceOfTheirFileSayWhatIsMeant) {
  EXPECT_EQ(load_error("http:\n  listen: 127.0.0.1\n  users:\n    alice: x\n"),
            "cfg.yaml:4:5: http.users must be the path of a file of name:password-hash lines, not the users themselves "
            "(docs/security.md: make the hashes with `openssl passwd -6`)");
}

TEST(ConfigLoad, HttpTlsAndUsers) {
  // The parse alone: the PEM files are check_on_host's (config_host_test).
  const auto c = parse_text("http:\n  listen: 0.0.0.0\n  port: 8443\n  users: /etc/u\n"
                            "  tls: { certificate: /etc/c.pem, key: /etc/c.key }\n", "h.yaml", Host::this_machine());
  ASSERT_TRUE(c.http);
  EXPECT_EQ(c.http->users, "/etc/u");
  ASSERT_TRUE(c.http->tls);
  EXPECT_EQ(c.http->tls->certificate, "/etc/c.pem");
  EXPECT_EQ(c.http->tls->key, "/etc/c.key");
  EXPECT_EQ(c.http->origin, "h.yaml:2:3");
  EXPECT_TRUE(warnings(c).empty());

  EXPECT_EQ(load_error("http: { tls: { certificate: c.pem } }\n"), "cfg.yaml:1:14: http.tls needs 'key', a PEM file");
  EXPECT_EQ(load_error("http: { tls: { certificate: c.pem, key: k, ca: x } }\n").substr(0, 30), "cfg.yaml:1:44: unknown key 'ca");
  EXPECT_EQ(load_error("http: { users: '' }\n"),
            "cfg.yaml:1:16: http.users must be the path of a file of name:password-hash lines");

  const auto open = warnings(load_text("http: { listen: '::' }\n", "o.yaml"));
  ASSERT_EQ(open.size(), 1u);
  EXPECT_EQ(open[0], "o.yaml:1:7: warning: http listens on :: without http.users: anyone who reaches the port reads the plant's "
                     "values and the monitor");
  const auto clear = warnings(load_text("http: { listen: 10.0.0.5, users: /etc/u }\n", "o.yaml"));
  ASSERT_EQ(clear.size(), 1u);
  EXPECT_TRUE(contains(clear[0], "without http.tls: passwords cross the network in clear")) << clear[0];
  for (const auto* loopback : {"127.0.0.1", "127.1.2.3", "::1"})
    EXPECT_TRUE(warnings(load_text(std::string("http: { listen: '") + loopback + "' }\n", "o.yaml")).empty()) << loopback;
}

TEST(ConfigLoad, MqttBrokerClientTopicAndTheirDefaults) {
  // The parse alone: the PEM file is check_on_host's (config_host_test).
  const auto c = parse_text("mqtt:\n  broker: mqtts://broker.example\n  client_id: site-17\n  username: bridge\n"
                            "  password_file: /etc/p\n  ca: /etc/ca.pem\n  version: 5\n  publish: { period: 30s, on_change: false }\n"
                            "  commands: true\n", "m.yaml", Host::this_machine());
  ASSERT_TRUE(c.mqtt);
  EXPECT_TRUE(c.mqtt->tls);
  EXPECT_EQ(c.mqtt->endpoint, (HostPort{"broker.example", 8883}));
  EXPECT_EQ(c.mqtt->topic, "unima/site-17");
  EXPECT_EQ(c.mqtt->version, 5);
  EXPECT_EQ(c.mqtt->period, 30s);
  EXPECT_FALSE(c.mqtt->on_change);
  EXPECT_TRUE(c.mqtt->commands);
  const auto plain = load_text("mqtt: { broker: 'mqtt://[::1]:1884', topic: plant/a }\n", "m.yaml");
  EXPECT_EQ(plain.mqtt->endpoint, (HostPort{"::1", 1884}));
  EXPECT_EQ(plain.mqtt->topic, "plant/a");
  EXPECT_TRUE(starts_with(plain.mqtt->client_id, "unima-bridge")) << plain.mqtt->client_id;
  EXPECT_EQ(plain.mqtt->period, 10s);

  EXPECT_EQ(load_error("mqtt: { broker: 'tcp://x' }\n"), "cfg.yaml:1:17: mqtt.broker: 'tcp://x' must start with mqtt:// or mqtts://");
  EXPECT_EQ(load_error("mqtt: { broker: 'mqtt://x', topic: 'a/#' }\n"),
            "cfg.yaml:1:36: mqtt.topic must be a topic prefix without wildcards (# +) or a trailing /");
  EXPECT_EQ(load_error("mqtt: { broker: 'mqtt://x', ca: c.pem }\n"), "cfg.yaml:1:33: mqtt.ca is for mqtts:// brokers");
  EXPECT_EQ(load_error("mqtt: { broker: 'mqtt://x', version: 4 }\n"), "cfg.yaml:1:38: mqtt.version must be 3.1.1 or 5");
  EXPECT_EQ(load_error("mqtt: { broker: 'mqtt://x', password_file: p }\n"), "cfg.yaml:1:44: mqtt.password_file needs mqtt.username");
  EXPECT_EQ(load_error("mqtt: { broker: 'mqtt://x:0' }\n").substr(0, 28), "cfg.yaml:1:17: mqtt.broker: ");
}

// mqtt.response_topics (SPEC §15): topic filters, `<topic>/reply/#` when absent; a
// filter an MQTT broker would not take, or one reaching the broker's $ topics, names its
// place in the file.
TEST(ConfigLoad, MqttResponseTopicsAreTopicFiltersWithReplyAsTheDefault) {
  EXPECT_EQ(load_text("mqtt: { broker: 'mqtt://x', topic: plant/a }\n", "m.yaml").mqtt->response_topics,
            std::vector<std::string>{"plant/a/reply/#"});
  EXPECT_EQ(load_text("mqtt: { broker: 'mqtt://x', topic: plant/a, response_topics: ['apps/+/replies', 'ops/#', plain] }\n",
                      "m.yaml")
                .mqtt->response_topics,
            (std::vector<std::string>{"apps/+/replies", "ops/#", "plain"}));
  EXPECT_TRUE(load_text("mqtt: { broker: 'mqtt://x', response_topics: [] }\n", "m.yaml").mqtt->response_topics.empty());

  const auto error = [](const std::string& list) {
    return load_error("mqtt: { broker: 'mqtt://x', response_topics: " + list + " }\n");
  };
  EXPECT_EQ(error("'a/#'"), "cfg.yaml:1:46: mqtt.response_topics must be a list of topic filters, e.g. [unima/" +
                               load_text("mqtt: { broker: 'mqtt://x' }\n", "m.yaml").mqtt->client_id + "/reply/#]");
  EXPECT_EQ(error("[ok, 'a/#/b']"), "cfg.yaml:1:51: mqtt.response_topics: not a topic filter: # must be the last level");
  EXPECT_EQ(error("['a/b#']"), "cfg.yaml:1:47: mqtt.response_topics: not a topic filter: + and # must each be a whole level (a/+/b, a/#)");
  EXPECT_EQ(error("['a+/b']"), "cfg.yaml:1:47: mqtt.response_topics: not a topic filter: + and # must each be a whole level (a/+/b, a/#)");
  EXPECT_EQ(error("['']"), "cfg.yaml:1:47: mqtt.response_topics: not a topic filter: it is empty");
  EXPECT_EQ(error("['$SYS/#']"),
            "cfg.yaml:1:47: mqtt.response_topics: not a topic filter: it starts with $ (the broker's own topics)");
  EXPECT_EQ(error("[\"a\\0b\"]"), "cfg.yaml:1:47: mqtt.response_topics: not a topic filter: it holds a NUL");

  // A reload that changes only where answers may go keeps the client and its session.
  const auto before = load_text("mqtt: { broker: 'mqtt://x' }\n", "m.yaml");
  const auto after = load_text("mqtt: { broker: 'mqtt://x', response_topics: ['apps/#'] }\n", "m.yaml");
  EXPECT_TRUE(before.mqtt->same_client(*after.mqtt));
}

TEST(ConfigLoad, SparkplugIdsBrokerAsMqttsAndDefaults) {
  Host host;
  host.name = "box-3";
  const auto c = parse_text("sparkplug:\n  broker: mqtts://broker.example\n  username: bridge\n  password_file: /etc/p\n"
                            "  ca: /etc/ca.pem\n  version: 5\n  group_id: plant-7\n  edge_node_id: bridge-17\n"
                            "  primary_host: scada-1\n  commands: true\n", "s.yaml", host);
  ASSERT_TRUE(c.sparkplug);
  EXPECT_TRUE(c.sparkplug->tls);
  EXPECT_EQ(c.sparkplug->endpoint, (HostPort{"broker.example", 8883}));
  EXPECT_EQ(c.sparkplug->username, "bridge");
  EXPECT_EQ(c.sparkplug->ca, "/etc/ca.pem");
  EXPECT_EQ(c.sparkplug->version, 5);
  EXPECT_EQ(c.sparkplug->group_id, "plant-7");
  EXPECT_EQ(c.sparkplug->edge_node_id, "bridge-17");
  EXPECT_EQ(c.sparkplug->primary_host, "scada-1");
  EXPECT_EQ(c.sparkplug->client_id, "unima-bridge-plant-7-bridge-17");
  EXPECT_TRUE(c.sparkplug->commands);
  const auto plain = parse_text("sparkplug: { broker: 'mqtt://127.0.0.1', group_id: g }\n", "s.yaml", host);
  EXPECT_EQ(plain.sparkplug->endpoint, (HostPort{"127.0.0.1", 1883}));
  EXPECT_EQ(plain.sparkplug->edge_node_id, "box-3");
  EXPECT_TRUE(plain.sparkplug->primary_host.empty());
  EXPECT_FALSE(plain.sparkplug->commands);

  EXPECT_EQ(load_error("sparkplug: { group_id: g }\n"),
            "cfg.yaml:1:12: sparkplug needs 'broker', e.g. mqtt://127.0.0.1:1883 or mqtts://broker.example:8883");
  EXPECT_EQ(load_error("sparkplug: { broker: 'mqtt://x' }\n"),
            "cfg.yaml:1:12: sparkplug needs 'group_id', the Sparkplug group of this edge node, e.g. plant-7");
  EXPECT_EQ(load_error("sparkplug: { broker: 'mqtt://x', group_id: 'a/b' }\n"),
            "cfg.yaml:1:44: sparkplug.group_id must be a name without / # or +");
  EXPECT_EQ(load_error("sparkplug: { broker: 'mqtt://x', group_id: g, primary_host: 'h+' }\n"),
            "cfg.yaml:1:61: sparkplug.primary_host must be a name without / # or +");
  EXPECT_EQ(load_error("sparkplug: { broker: 'mqtt://x', group_id: g, ca: c.pem }\n"),
            "cfg.yaml:1:51: sparkplug.ca is for mqtts:// brokers");
  EXPECT_EQ(load_error("sparkplug: { broker: 'mqtt://x', group_id: g, password_file: p }\n"),
            "cfg.yaml:1:62: sparkplug.password_file needs sparkplug.username");
  EXPECT_EQ(load_error("sparkplug: { broker: 'mqtt://x', group_id: g, topic: t }\n").substr(0, 56),
            "cfg.yaml:1:47: unknown key 'topic' in sparkplug (known: ");
}

}  // namespace
}  // namespace unima::config
