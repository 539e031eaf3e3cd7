// Who may send what through the gateway on the TLS port (SPEC §14, issue 31): a role's
// `write` list names the foreign slaves by "unit 3" and "units 5-9" beside its banks and
// registers; reads (functions 1-4) are forwarded for everyone, any other function only to
// a unit the role names. Malformed entries fail at file:line:column.

#include <gtest/gtest.h>

#include <string>

#include "config/config.hpp"
#include "modbus/write_rights.hpp"
#include "tests/support/error_message.hpp"

namespace unima {
namespace {

config::Config load(const std::string& write) {
  return config::parse_text("modbus:\n"
                            "  tls: { certificate: s.pem, key: s.key, ca: ca.pem,\n"
                            "         roles: { operator: { write: " + write + " } } }\n",
                            "r.yaml", config::Host{});
}

std::string error(const std::string& write) {
  return test_support::error_message<config::ConfigError>([&] { (void)load(write); });
}

const modbus::WriteRights& operator_rights(const config::Config& c) { return c.modbus.tls->roles.at("operator"); }

TEST(GatewayRights, ReadsAreForwardedForEveryoneWritesOnlyToTheUnitsNamed) {
  auto rights = modbus::WriteRights::nothing();
  rights.allow_units(3, 3);
  rights.allow_units(5, 9);
  for (const std::uint8_t read : {0x01, 0x02, 0x03, 0x04}) {
    EXPECT_TRUE(modbus::WriteRights::nothing().may_forward(4, read)) << int{read};
    EXPECT_TRUE(rights.may_forward(4, read)) << int{read};
  }
  // Writes, and functions the bridge does not read (23, 43, a vendor's): only to the units named.
  for (const std::uint8_t other : {0x05, 0x06, 0x0F, 0x10, 0x17, 0x2B, 0x41}) {
    EXPECT_TRUE(rights.may_forward(3, other)) << int{other};
    EXPECT_TRUE(rights.may_forward(5, other)) << int{other};
    EXPECT_TRUE(rights.may_forward(9, other)) << int{other};
    EXPECT_FALSE(rights.may_forward(4, other)) << int{other};
    EXPECT_FALSE(rights.may_forward(10, other)) << int{other};
    EXPECT_FALSE(modbus::WriteRights::nothing().may_forward(3, other)) << int{other};
    EXPECT_TRUE(modbus::WriteRights::everything().may_forward(3, other)) << int{other};
  }
  // Units are not registers: a role that may write units writes no bank.
  EXPECT_FALSE(rights.allows(3, 1));
  EXPECT_FALSE(rights.allows_nothing());
}

TEST(GatewayRights, ARoleNamesUnitsBesideBanksAndRegisters) {
  const auto c = load("[W, \"unit 3\", \"units 5-9\", unit 17]");
  const auto& rights = operator_rights(c);
  for (unsigned unit = 0; unit < 256; ++unit)
    EXPECT_EQ(rights.may_forward(static_cast<std::uint8_t>(unit), 0x06),
              unit == 3 || (unit >= 5 && unit <= 9) || unit == 17)
        << unit;
  EXPECT_TRUE(rights.allows(0x3000, 16));  // W, at its default base
  EXPECT_FALSE(operator_rights(load("[W]")).may_forward(3, 0x06));
  EXPECT_FALSE(operator_rights(load("[]")).may_forward(3, 0x10));
}

// With several master lines a role's unit may be routed by any of them (SPEC §18): no
// warning for a unit the second line's gateway forwards.
TEST(GatewayRights, AUnitAnyMasterLineRoutesIsNoWarning) {
  const auto c = config::parse_text("modbus:\n"
                                    "  lines:\n"
                                    "    field: { device: /dev/ttyS1, role: master, gateway: { units: [3] } }\n"
                                    "    meters: { device: /dev/ttyS2, role: master, gateway: { units: [9] } }\n"
                                    "  tls: { certificate: s.pem, key: s.key, ca: ca.pem,\n"
                                    "         roles: { operator: { write: [\"unit 3\", \"unit 9\"] } } }\n",
                                    "r.yaml", config::Host{});
  EXPECT_TRUE(config::warnings(c).empty()) << config::warnings(c).front();
  EXPECT_TRUE(operator_rights(c).may_forward(9, 0x06));
}

// A right to a unit the gateway does not forward is never used: said at the item, and the
// config still loads (the units may be cut down on purpose for a while).
TEST(GatewayRights, AUnitTheGatewayDoesNotForwardIsWarnedOfAtItsItem) {
  const auto routed = [](const std::string& write) {
    return config::parse_text("modbus:\n"
                              "  mode: master\n"
                              "  rtu: { device: /dev/ttyUSB0 }\n"
                              "  gateway: { units: [3, 5-7] }\n"
                              "  tls: { certificate: s.pem, key: s.key, ca: ca.pem,\n"
                              "         roles: { operator: { write: " + write + " } } }\n",
                              "r.yaml", config::Host{});
  };
  EXPECT_TRUE(config::warnings(routed("[W, \"unit 3\", \"units 5-7\"]")).empty());
  EXPECT_EQ(config::warnings(routed("[\"unit 4\"]")),
            std::vector<std::string>{"r.yaml:6:39: warning: modbus.tls.roles.operator.write: unit 4 is not in "
                                     "modbus.gateway.units; no request reaches it and this right is never used"});
  EXPECT_EQ(config::warnings(routed("[\"units 6-9\"]")),
            std::vector<std::string>{"r.yaml:6:39: warning: modbus.tls.roles.operator.write: units 8, 9 are not in "
                                     "modbus.gateway.units; no request reaches them and this right is never used"});
  const auto without_gateway = load("[W, \"units 5-9\"]");
  EXPECT_TRUE(operator_rights(without_gateway).may_forward(5, 0x06));
  EXPECT_EQ(config::warnings(without_gateway),
            std::vector<std::string>{"r.yaml:3:42: warning: modbus.tls.roles.operator.write: units 5-9 are named, but there "
                                     "is no modbus.gateway; this right is never used"});
}

TEST(GatewayRights, AMalformedUnitEntryFailsAtItsPosition) {
  EXPECT_EQ(error("[W, \"unit 300\"]"), "r.yaml:3:42: modbus.tls.roles.operator.write: unit 300 is outside 1..247");
  EXPECT_EQ(error("[\"unit 0\"]"), "r.yaml:3:39: modbus.tls.roles.operator.write: unit 0 is outside 1..247");
  EXPECT_EQ(error("[\"units 9-5\"]"),
            "r.yaml:3:39: modbus.tls.roles.operator.write: the range 9-5 ends before it begins");
  EXPECT_EQ(error("[\"unit three\"]"),
            "r.yaml:3:39: modbus.tls.roles.operator.write: 'unit three' is not a unit id or a range of them (write e.g. "
            "\"unit 3\" or \"units 5-9\")");
  EXPECT_EQ(error("[\"units\"]"),
            "r.yaml:3:39: modbus.tls.roles.operator.write: 'units' is not a unit id or a range of them (write e.g. "
            "\"unit 3\" or \"units 5-9\")");
}

}  // namespace
}  // namespace unima
