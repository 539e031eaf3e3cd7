// modbus.gateway in the config (SPEC §14, docs/gateway.md): units as ids and ranges, the
// priority peers, wait, timeout and cache; and its errors, each naming its key with
// file:line:column.

#include <gtest/gtest.h>

#include "config/config.hpp"
#include "tests/support/error_message.hpp"

namespace unima::config {
namespace {

using namespace std::chrono_literals;

const std::string rtu_master =
    "modbus:\n"
    "  mode: master\n"
    "  rtu: { device: /dev/ttyUSB0, baud: 38400 }\n";

Config load(const std::string& yaml) { return parse_text(yaml, "g.yaml", Host{}); }

std::string error(const std::string& yaml) {
  return test_support::error_message<ConfigError>([&] { (void)load(yaml); });
}

PeerAddress address(std::string_view text) {
  PeerAddress a{};
  EXPECT_TRUE(parse_peer_address(text, a)) << text;
  return a;
}

TEST(GatewayConfig, UnitsAsIdsAndRangesWithPriorityWaitTimeoutAndCache) {
  const auto c = load(rtu_master +
                      "  gateway:\n"
                      "    units: [2-9, 17]\n"
                      "    priority: [10.0.0.5, 192.168.1.0/24]\n"
                      "    wait: 3s\n"
                      "    timeout: 400ms\n"
                      "    cache: 250ms\n");
  ASSERT_TRUE(c.modbus.gateway());
  const auto& g = *c.modbus.gateway();
  for (unsigned unit = 0; unit < 256; ++unit)
    EXPECT_EQ(g.routes(static_cast<std::uint8_t>(unit)), (unit >= 2 && unit <= 9) || unit == 17) << unit;
  EXPECT_TRUE(g.priority.allows(address("10.0.0.5")));
  EXPECT_TRUE(g.priority.allows(address("192.168.1.77")));
  EXPECT_FALSE(g.priority.allows(address("10.0.0.6")));
  EXPECT_EQ(g.wait, 3s);
  EXPECT_EQ(g.timeout, std::optional<Duration>(400ms));
  EXPECT_EQ(g.cache, 250ms);
  EXPECT_EQ(g.origin, "g.yaml:5:5");
}

TEST(GatewayConfig, DefaultsAreTwoSecondsOfWaitTheProfilesTimeoutAndNoCache) {
  const auto c = load(rtu_master + "  gateway: { units: [3] }\n");
  ASSERT_TRUE(c.modbus.gateway());
  EXPECT_EQ(c.modbus.gateway()->wait, 2s);
  EXPECT_FALSE(c.modbus.gateway()->timeout);
  EXPECT_EQ(c.modbus.gateway()->cache, 0ms);
  EXPECT_TRUE(c.modbus.gateway()->priority.empty());
  EXPECT_FALSE(c.modbus.gateway()->reads_only) << "every function is forwarded unless functions: read";
  EXPECT_FALSE(load(rtu_master).modbus.gateway());
}

TEST(GatewayConfig, FunctionsReadForwardsReadsOnlyAndAnotherWordIsAnError) {
  EXPECT_TRUE(load(rtu_master + "  gateway: { units: [3], functions: read }\n").modbus.gateway()->reads_only);
  EXPECT_FALSE(load(rtu_master + "  gateway: { units: [3], functions: all }\n").modbus.gateway()->reads_only);
  EXPECT_NE(error(rtu_master + "  gateway: { units: [3], functions: writes }\n").find("'writes' is not one of: read, all"),
            std::string::npos);
}

TEST(GatewayConfig, WithoutMasterModeIsAnErrorNamingTheKey) {
  EXPECT_EQ(error("modbus:\n"
                  "  gateway: { units: [3] }\n"),
            "g.yaml:2:12: modbus.gateway forwards to the line the master drives: it needs modbus.mode: master");
}

TEST(GatewayConfig, TheBridgesOwnAddressIsAnErrorAtTheItemThatNamesIt) {
  EXPECT_EQ(error(rtu_master +
                  "  address: 5\n"
                  "  gateway:\n"
                  "    units: [2, 4-6]\n"),
            "g.yaml:6:16: modbus.gateway.units: unit 5 is the bridge's own modbus.address, which serves the banks: "
            "leave it out");
  // The default address 1.
  EXPECT_NE(error(rtu_master + "  gateway: { units: [1-3] }\n").find("unit 1 is the bridge's own modbus.address"),
            std::string::npos);
}

// Issue 43, finding 13: `[5, 5]` or a range over an id already listed is a slip, named at
// its second mention with its first.
TEST(GatewayConfig, AUnitListedTwiceIsAnErrorNamingBothPlaces) {
  EXPECT_EQ(error(rtu_master + "  gateway: { units: [5, 5] }\n"),
            "g.yaml:4:25: modbus.gateway.units: unit 5 is listed twice (first at g.yaml:4:22)");
  EXPECT_EQ(error(rtu_master + "  gateway: { units: [2-9, 17, 9-12] }\n"),
            "g.yaml:4:31: modbus.gateway.units: unit 9 is listed twice (first at g.yaml:4:22)");
}

TEST(GatewayConfig, AUnitOutsideOneTo247IsAnErrorNamingTheKey) {
  EXPECT_EQ(error(rtu_master + "  gateway: { units: [3, 248] }\n"),
            "g.yaml:4:25: modbus.gateway.units: unit 248 is outside 1..247");
  EXPECT_EQ(error(rtu_master + "  gateway: { units: [0-4] }\n"),
            "g.yaml:4:22: modbus.gateway.units: unit 0 is outside 1..247");
  EXPECT_EQ(error(rtu_master + "  gateway: { units: [240-250] }\n"),
            "g.yaml:4:22: modbus.gateway.units: unit 250 is outside 1..247");
}

TEST(GatewayConfig, MalformedKeysNameThemselves) {
  EXPECT_EQ(error(rtu_master + "  gateway: { units: [9-3] }\n"),
            "g.yaml:4:22: modbus.gateway.units: the range 9-3 ends before it begins");
  EXPECT_EQ(error(rtu_master + "  gateway: { units: [three] }\n"),
            "g.yaml:4:22: modbus.gateway.units: 'three' is not a unit id or a range of them (write e.g. 3 or 2-9)");
  EXPECT_EQ(error(rtu_master + "  gateway: { priority: [10.0.0.5] }\n"),
            "g.yaml:4:12: modbus.gateway.units must list the unit ids forwarded to the line, e.g. [2-9, 17]");
  EXPECT_NE(error(rtu_master + "  gateway: { units: [3], priority: [10.0.0.300] }\n").find("modbus.gateway.priority: "),
            std::string::npos);
  EXPECT_NE(error(rtu_master + "  gateway: { units: [3], wait: 0s }\n").find("must be longer than 0"), std::string::npos);
  EXPECT_NE(error(rtu_master + "  gateway: { units: [3], route: all }\n").find("route"), std::string::npos);
}

TEST(GatewayConfig, AMasterOnATcpTargetCannotForwardYet) {
  EXPECT_NE(error("modbus:\n"
                  "  mode: master\n"
                  "  master: { tcp: 127.0.0.1:1502 }\n"
                  "  gateway: { units: [3] }\n")
                .find("g.yaml:4:12: modbus.gateway forwards RTU frames to modbus.rtu"),
            std::string::npos);
}

}  // namespace
}  // namespace unima::config
