// Issue #3 end to end: every device type's table served over Modbus from feed telegrams,
// mapping of A and B, read and write blocks, and `unima-bridge map`.

#include <cstdio>
#include <sys/wait.h>

#include <tuple>

#include "banks/table_catalog.hpp"
#include "tests/integration/bridge_fixture.hpp"

namespace unima::test {
namespace {

class DeviceType : public BridgeTest, public ::testing::WithParamInterface<std::string> {};

// Register n of the device carries 1000 + n; each named register must read its own value.
TEST_P(DeviceType, EveryNamedRegisterReadsWhatItsDeviceSent) {
  const auto* table = banks::find_device_type(GetParam());
  ASSERT_NE(table, nullptr);
  config.banks = "{ D1: 0x1100 }";
  config.devices = "{ D1: { type: " + GetParam() + ", address: 5 } }";
  start();
  auto feed = feed_client();
  std::string values;
  for (std::uint16_t n = 0; n < table->length(); ++n) values += (n ? "," : "") + std::to_string(1000 + n);
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":0,"values":[)" + values + "]}", 0x1100, 1000);
  ModbusClient client(config.modbus_port);
  for (const auto& reg : table->registers) {
    const auto got = client.read_input(0x1100 + reg.offset, 1);
    ASSERT_TRUE(got) << reg.id;
    EXPECT_EQ((*got)[0], 1000 + reg.offset) << GetParam() << "." << reg.id;
  }
  // The bank is the seed's window of 64 whatever the type (seed §6.1): past the table, 0x7FFF.
  const auto whole = client.read_input(0x1100, 64);
  ASSERT_TRUE(whole) << client.last_error();
  for (std::uint16_t n = 0; n < 64; ++n)
    EXPECT_EQ((*whole)[n], n < table->length() ? 1000 + n : 0x7FFF) << GetParam() << " +" << n;
  // One past the window is not served.
  EXPECT_FALSE(client.read_input(0x1100, 65));
  EXPECT_EQ(client.last_error(), EMBXILADD);
}

INSTANTIATE_TEST_SUITE_P(AllNine, DeviceType,
                         ::testing::Values("unigen-chp", "unigen-tem", "unigen-mve", "microgen-sync", "nsu2", "uis",
                                           "uvr", "usc", "bridge-tem"),
                         [](const auto& info) {
                           auto name = info.param;
                           for (auto& c : name) c = c == '-' ? '_' : c;
                           return name;
                         });

// Issue 30 point 3: a SCADA template written for the hardware reads every D_N as
// 0x1N00 × 64 (seed §6.1: 0x1100÷0x113F for every device type), with function 4 and with
// function 3 (answered like 4, SPEC §3). A USC's table is 40 long, a UVR's 49.
TEST_F(BridgeTest, ATemplateOf64RegistersReadsAUscAndAUvrWhole) {
  config.banks = "{ D2: 0x1200, D3: 0x1300 }";
  config.devices = "{ D2: { type: usc, address: 5 }, D3: { type: uvr, address: 6 } }";
  start();
  auto feed = feed_client();
  const std::vector<std::tuple<int, int, std::uint16_t>> devices = {{5, 0x1200, 40}, {6, 0x1300, 49}};
  for (const auto& [address, base, length] : devices) {
    ASSERT_EQ(banks::find_device_type(address == 5 ? "usc" : "uvr")->length(), length);
    std::string values;
    for (int n = 0; n < length; ++n) values += (n ? "," : "") + std::to_string(base + n);
    feed_and_wait(feed, R"({"addr":)" + std::to_string(address) + R"(,"slot":0,"offset":0,"values":[)" + values + "]}",
                  base + length - 1, static_cast<std::uint16_t>(base + length - 1));
  }
  ModbusClient client(config.modbus_port);
  for (const auto& [address, base, length] : devices) {
    std::vector<std::uint16_t> expected(64, 0x7FFF);
    for (int n = 0; n < length; ++n) expected[n] = static_cast<std::uint16_t>(base + n);
    EXPECT_EQ(client.read_input(base, 64), expected) << std::hex << base << " fn 4, error " << client.last_error();
    EXPECT_EQ(client.read_holding(base, 64), expected) << std::hex << base << " fn 3, error " << client.last_error();
    // Past the window nothing is served: a read that crosses its end is refused whole.
    EXPECT_FALSE(client.read_input(base + 1, 64));
    EXPECT_EQ(client.last_error(), EMBXILADD);
    EXPECT_FALSE(client.read_holding(base + 0x3F, 2));
    EXPECT_EQ(client.last_error(), EMBXILADD);
  }
  // The same bytes on the wire: 0x1227 is the USC's last register, 0x1228..0x123F read
  // 0x7FFF like reserves, 0x1240 is nobody's.
  EXPECT_EQ(round_trip(config.modbus_port, {0, 1, 0, 0, 0, 6, 1, 0x04, 0x12, 0x27, 0x00, 0x02}),
            (Bytes{0, 1, 0, 0, 0, 7, 1, 0x04, 0x04, 0x12, 0x27, 0x7F, 0xFF}));
  EXPECT_EQ(round_trip(config.modbus_port, {0, 1, 0, 0, 0, 6, 1, 0x04, 0x12, 0x3F, 0x00, 0x01}),
            (Bytes{0, 1, 0, 0, 0, 5, 1, 0x04, 0x02, 0x7F, 0xFF}));
  EXPECT_EQ(round_trip(config.modbus_port, {0, 1, 0, 0, 0, 6, 1, 0x04, 0x12, 0x40, 0x00, 0x01}),
            (Bytes{0, 1, 0, 0, 0, 3, 1, 0x84, 0x02}));
  // Past its table a telegram is refused whole, so those registers stay 0x7FFF.
  feed.send(std::string(R"({"addr":5,"slot":0,"offset":39,"values":[1,2]})") + "\n");
  const auto answer = feed.read_line();
  ASSERT_TRUE(answer);
  EXPECT_NE(answer->find("run past the end of bank D2 (usc: 40 registers)"), std::string::npos) << *answer;
  EXPECT_EQ(client.read_input(0x1227, 2), (std::vector<std::uint16_t>{0x1227, 0x7FFF}));
}

// Issue 30 point 5: sources of W, C and S_N carry tenths already, and A saturates them like
// any result (SPEC §1): 0x8000 (−32768) is outside −32767..32766 and reads 0x8001. A
// master's 0x7FFF is its "not measured" and stays so.
TEST_F(BridgeTest, BankASaturatesMinus32768FromWCAndS) {
  config.devices =
      "{ D1: { type: unigen-chp, address: 5 } }\n"
      "mapping:\n"
      "  A: [ W+0x00, C+0x00, S1+0x00, W+0x01 ]";
  config.blocks = "  - { type: write, register: 0x0200, output: 1 }\n";
  start();
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.write(0x0100, 0x8000));  // W+0x00 (W at 0x0100 in these tests)
  ASSERT_TRUE(client.write(0x0200, 0x8000));  // the write block: user output 1 = C+0x00
  ASSERT_TRUE(client.write(0x0101, 0x7FFF));  // W+0x01
  auto feed = feed_client();
  feed_and_wait(feed, R"({"addr":5,"slot":1,"offset":0,"values":[-32768]})", 0x2100, 0x8000);  // S1+0x00
  EXPECT_EQ(client.read_input(0x1020, 1), std::vector<std::uint16_t>{0x8000});  // C itself as written
  EXPECT_EQ(client.read_input(0x1000, 4), (std::vector<std::uint16_t>{0x8001, 0x8001, 0x8001, 0x7FFF}));
  EXPECT_EQ(client.read_holding(0x1000, 4), (std::vector<std::uint16_t>{0x8001, 0x8001, 0x8001, 0x7FFF}));
  // Inside the range a value is A's as it is.
  ASSERT_TRUE(client.write(0x0100, 0x8001));
  ASSERT_TRUE(client.write(0x0101, 0xFFFF));
  EXPECT_EQ(client.read_input(0x1000, 4), (std::vector<std::uint16_t>{0x8001, 0x8001, 0x8001, 0xFFFF}));
}

// Seed §6.2.4.6: the UIS's cylinder masks are bit registers, 0 while the UIS is off-line.
TEST_F(BridgeTest, AnOffLineUisReadsZeroInItsCylinderMasks) {
  config.banks = "{ D1: 0x1100 }";
  config.devices = "{ D1: { type: uis, address: 5 } }";
  start();
  ModbusClient client(config.modbus_port);
  EXPECT_EQ(client.read_input(0x1108, 8), (std::vector<std::uint16_t>{0xFFFF, 0xFFFF, 0xFFFF, 0x7FFF, 0, 0, 0x7FFF, 0}));
}

TEST_F(BridgeTest, AnUnconfiguredDeviceBankDoesNotExist) {
  start();
  ModbusClient client(config.modbus_port);
  EXPECT_FALSE(client.read_input(0x1200, 1));  // D2 at its default base, no device
  EXPECT_EQ(client.last_error(), EMBXILADD);
}

class MappingAndBlocks : public BridgeTest {
 protected:
  void SetUp() override {
    BridgeTest::SetUp();
    config.banks = "{ D1: 0x1100 }";
    config.modbus_extra = "";
    config.devices =
        "{ D1: { type: unigen-chp, address: 5 } }\n"
        "mapping:\n"
        "  A: [ D1.oil_temperature, D1+0x01 ]\n"
        "  B: [ D1+0x11.7, X.2 ]\n"
        "blocks:\n"
        "  - { type: read, register: 0x0200, source: D1.engine_speed }\n"
        "  - { type: write, register: 0x0201, output: 1 }\n"
        "  - { type: write, register: 0x0202, output: 16 }";
    start();
    feed = std::make_unique<Socket>(feed_client());
  }
  std::unique_ptr<Socket> feed;
};

TEST_F(MappingAndBlocks, BankAShowsItsSources) {
  ModbusClient client(config.modbus_port);
  EXPECT_EQ(client.read_input(0x1000, 3), (std::vector<std::uint16_t>{0x7FFF, 0x7FFF, 0x7FFF}));
  feed_and_wait(*feed, R"({"addr":5,"slot":0,"offset":33,"values":[853]})", 0x1000, 853);
  // Bank A is in 0.1 of the source's unit (seed §6.2.1): the speed, in 1 min⁻¹, times 10.
  feed_and_wait(*feed, R"({"addr":5,"slot":0,"offset":1,"values":[1500]})", 0x1001, 15000);
  EXPECT_EQ(client.read_input(0x1000, 3), (std::vector<std::uint16_t>{853, 15000, 0x7FFF}));
  // The register changes with its source, read right after the telegram took effect.
  feed_and_wait(*feed, R"({"addr":5,"slot":0,"offset":33,"values":[854]})", 0x1121, 854);
  EXPECT_EQ(client.read_input(0x1000, 1), std::vector<std::uint16_t>{854});
}

TEST_F(MappingAndBlocks, BankBShowsItsSourceBits) {
  ModbusClient client(config.modbus_port);
  feed_and_wait(*feed, R"({"addr":5,"slot":0,"offset":17,"values":[128]})", 0x1010, 0x0001);
  ASSERT_TRUE(client.write(0x3010, 0x0004));  // X bit 2
  EXPECT_EQ(client.read_input(0x1010, 1), std::vector<std::uint16_t>{0x0003});
}

TEST_F(MappingAndBlocks, ReadBlockAndWriteBlocks) {
  ModbusClient client(config.modbus_port);
  feed_and_wait(*feed, R"({"addr":5,"slot":0,"offset":1,"values":[1480]})", 0x0200, 1480);
  ASSERT_TRUE(client.write(0x0201, 2345));
  EXPECT_TRUE(feed->wait_for_line(R"({"bank":"C","offset":0,"value":2345})"));
  ASSERT_TRUE(client.write(0x0202, 7));
  EXPECT_TRUE(feed->wait_for_line(R"({"bank":"C","offset":15,"value":7})"));
  EXPECT_EQ(client.read_input(0x1020, 1), std::vector<std::uint16_t>{2345});  // C+0x00 = UsrAO 1
  EXPECT_EQ(client.read_input(0x102F, 1), std::vector<std::uint16_t>{7});     // C+0x0F = UsrAO 16
  EXPECT_FALSE(client.read_input(0x0201, 1));  // write-only
  EXPECT_EQ(client.last_error(), EMBXILADD);
  EXPECT_FALSE(client.write(0x0200, 1));  // read-only
  EXPECT_EQ(client.last_error(), EMBXILADD);
}

// SPEC §1: A reads 0x7FFF while its source is off-line, whatever the source's kind (a bit
// word read 0, a 32-bit half and a byte pair 0xFFFF, an ASCII pair 0x2020 before).
TEST_F(BridgeTest, BankAReadsNotMeasuredForEveryKindOfSourceOffLine) {
  config.banks = "{ D1: 0x1100, D2: 0x1200, D3: 0x1300 }";
  config.devices =
      "{ D1: { type: unigen-chp, address: 5 }, D2: { type: uis, address: 6 }, D3: { type: nsu2, address: 7 } }\n"
      "mapping:\n"
      "  A: [ D1+0x00, D1.operating_hours_low, D1.operating_hours_high, D2+0x28, D3+0x28, D1.engine_speed ]";
  start();
  ModbusClient client(config.modbus_port);
  EXPECT_EQ(client.read_input(0x1000, 6), std::vector<std::uint16_t>(6, 0x7FFF));
  auto feed = feed_client();
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":0,"values":[129,1500,7,0]})", 0x1000, 129);
  EXPECT_EQ(client.read_input(0x1000, 6), (std::vector<std::uint16_t>{129, 7, 0, 0x7FFF, 0x7FFF, 15000}));
}

TEST(MapCommand, FourDeviceTypesListEveryRegisterWithNamesAndUnits) {
  const auto [status, csv] =
      run(std::string(UNIMA_BRIDGE_CLI) + " map --format csv --config " UNIMA_SOURCE_DIR "/config/examples/four-devices.yaml");
  ASSERT_EQ(status, 0) << csv;
  EXPECT_NE(csv.find("0x1121,D1,0x21,oil_temperature,Teplota oleje,analog,°C,0.1,R,"), std::string::npos) << csv;
  const std::vector<std::pair<std::uint16_t, std::string>> devices = {
      {0x1100, "unigen-chp"}, {0x1200, "uvr"}, {0x1300, "usc"}, {0x1400, "uis"}};
  for (const auto& [base, type] : devices) {
    const auto* table = banks::find_device_type(type);
    ASSERT_NE(table, nullptr);
    for (const auto& reg : table->registers) {
      char address[8];
      std::snprintf(address, sizeof address, "0x%04X", base + reg.offset);
      const auto row = csv.find(std::string("\n") + address + ",");
      ASSERT_NE(row, std::string::npos) << type << " " << reg.id;
      const auto line = csv.substr(row + 1, csv.find('\n', row + 1) - row - 1);
      // A byte or ASCII pair's register is a row per byte, named by the table's id of the byte.
      bool named = line.find("," + reg.id + ",") != std::string::npos;
      for (const auto& field : reg.fields) named = named || line.find("," + field.id + ",") != std::string::npos;
      EXPECT_TRUE(named) << reg.id << ": " << line;
    }
  }
  // Past its table of 40 the USC's D_N goes on to +0x3F, listed as reserves (seed §6.1).
  EXPECT_NE(csv.find("\n0x1328,D3,0x28,reserve_28,Rezerva,reserve,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\n0x133F,D3,0x3F,reserve_3f,Rezerva,reserve,"), std::string::npos) << csv;
  EXPECT_EQ(csv.find("\n0x1340,"), std::string::npos) << csv;
  const auto json =
      run(std::string(UNIMA_BRIDGE_CLI) + " map --format json --config " UNIMA_SOURCE_DIR "/config/examples/four-devices.yaml");
  EXPECT_EQ(json.status, 0);
  EXPECT_NE(json.output.find("\"id\": \"oil_temperature\""), std::string::npos);
  const auto xml = run(std::string(UNIMA_BRIDGE_CLI) + " map --format xml --config x.yaml");
  EXPECT_EQ(xml.output.find("unknown format"), std::string("unima-bridge map: ").size());
  EXPECT_EQ(xml.status, 2);
}

}  // namespace
}  // namespace unima::test
