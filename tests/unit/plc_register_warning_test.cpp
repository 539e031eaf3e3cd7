// A decimal 3xxxx or 4xxxx in a key that holds a register address is the PLC numbering
// habit: taken as written, with a warning naming the address it would mean; six digits
// are no address at all (issue 30, 6). Every such key reads through YamlReader::register_address.

#include <gtest/gtest.h>

#include <string>

#include "config/config.hpp"
#include "tests/support/error_message.hpp"

namespace unima::config {
namespace {

Config parse(const std::string& text) { return parse_text(text, "bridge.yaml", Host{}); }

TEST(PlcRegisterWarning, EveryKeyHoldingARegisterAddressWarnsOfThePlcNumbering) {
  const auto config = parse(
      "modbus:\n"
      "  tls: { certificate: s.pem, key: s.key, ca: ca.pem, roles: { op: { write: [40001] } } }\n"
      "banks: { W: 40001 }\n"
      "devices: { D1: { type: unigen-chp, address: 5 } }\n"
      "blocks:\n"
      "  - { type: read, register: 30001, source: D1+0x01 }\n"
      "monitor:\n"
      "  indicators: [ { address: 3, register: 40010 } ]\n");
  const auto found = warnings(config);
  ASSERT_EQ(found.size(), 4u) << ::testing::PrintToString(found);
  EXPECT_EQ(found[0], "bridge.yaml:3:13: warning: register 40001 is taken as address 0x9C41; if holding register 40001 "
                      "(PLC numbering, from 1) was meant, write its address 0x0000; write 0x9C41 to keep this address "
                      "without this warning");
  EXPECT_NE(found[1].find("bridge.yaml:6:29: warning: register 30001 is taken as address 0x7531; if input register "
                          "30001 (PLC numbering, from 1) was meant, write its address 0x0000"),
            std::string::npos);
  EXPECT_NE(found[2].find("bridge.yaml:8:41: warning: register 40010 is taken as address 0x9C4A; if holding register "
                          "40010 (PLC numbering, from 1) was meant, write its address 0x0009"),
            std::string::npos);
  EXPECT_NE(found[3].find("bridge.yaml:2:77: warning: register 40001 is taken"), std::string::npos)
      << ::testing::PrintToString(found);
}

TEST(PlcRegisterWarning, HexOrOtherNumbersAreNoWarningAndSixDigitsAreAnError) {
  EXPECT_TRUE(warnings(parse("devices: { D1: { type: unigen-chp, address: 5 } }\n"
                             "blocks: [ { type: read, register: 0x9C41, source: D1+0x01 },\n"
                             "          { type: read, register: 29999, source: D1+0x01 },\n"
                             "          { type: read, register: 50000, source: D1+0x01 } ]\n"))
                  .empty());
  EXPECT_EQ(test_support::error_message<ConfigError>([] {
              (void)parse("devices: { D1: { type: unigen-chp, address: 5 } }\n"
                          "blocks: [ { type: read, register: 400001, source: D1+0x01 } ]\n");
            }),
            "bridge.yaml:2:35: 400001 is not a register address (0x0000..0xFFFF); if holding register 400001 (PLC "
            "numbering, from 1) was meant, write its address 0x0000");
}

}  // namespace
}  // namespace unima::config
