// SPEC §11 access control, the pure parts: which registers a client may write
// (modbus::WriteRights, asked by the request handler before it writes) and which peers may
// connect (config::PeerAllowList, `modbus.tcp.allow`).

#include <gtest/gtest.h>

#include <array>
#include <string>
#include <variant>
#include <vector>

#include "config/peer_allow_list.hpp"
#include "modbus/slave_session.hpp"
#include "modbus/write_rights.hpp"
#include "tests/support/map_registers.hpp"

namespace unima {
namespace {

using Bytes = std::vector<std::uint8_t>;

TEST(WriteRights, EverythingNothingAndListedRanges) {
  EXPECT_TRUE(modbus::WriteRights::everything().allows(0xFFFF, 1));
  EXPECT_FALSE(modbus::WriteRights::nothing().allows(0x0100, 1));
  EXPECT_TRUE(modbus::WriteRights::nothing().allows_nothing());

  auto rights = modbus::WriteRights::nothing();
  rights.allow(0x3000, 0x300F);  // W
  rights.allow(0x3010, 0x3010);  // X, beside it: one range
  rights.allow(0x0201, 0x0201);
  ASSERT_EQ(rights.ranges().size(), 2u);
  EXPECT_TRUE(rights.allows(0x3000, 17));   // W and X in one fn-16
  EXPECT_FALSE(rights.allows(0x3000, 18));  // one past X
  EXPECT_FALSE(rights.allows(0x2FFF, 2));   // one before W
  EXPECT_TRUE(rights.allows(0x0201, 1));
  EXPECT_FALSE(rights.allows(0x0200, 2));
  EXPECT_FALSE(rights.allows(0x0201, 0));
}

struct RightsServing : ::testing::Test {
  test_support::MapRegisters registers{{{0x0011, 0x1234}}, {{0x0100, 0}, {0x0101, 0}, {0x0200, 0}}};
  modbus::HandlerOptions options;
  std::array<std::uint8_t, modbus::max_pdu_size> out{};
  modbus::Served serve(const Bytes& pdu, const modbus::WriteRights& rights) {
    return modbus::serve_request(modbus::Link::tcp, modbus::Recipient::this_slave, pdu, out, registers, options,
                                 &rights);
  }
};

// SPEC §11: a write outside the rights is exception 01 and changes nothing; reads are free.
TEST_F(RightsServing, AWriteOutsideTheRightsIsIllegalFunctionAndChangesNothing) {
  auto rights = modbus::WriteRights::nothing();
  rights.allow(0x0100, 0x0101);

  auto served = serve({0x06, 0x02, 0x00, 0x00, 0x05}, rights);
  EXPECT_EQ((Bytes{out[0], out[1]}), (Bytes{0x86, 0x01}));
  EXPECT_EQ(served.state, modbus::TransactionState::err01);
  EXPECT_TRUE(served.fault);
  EXPECT_EQ(registers.writable.at(0x0200), 0);

  // A fn-16 reaching one register past the rights writes none of them.
  served = serve({0x10, 0x01, 0x00, 0x00, 0x03, 0x06, 0, 1, 0, 2, 0, 3}, rights);
  EXPECT_EQ((Bytes{out[0], out[1]}), (Bytes{0x90, 0x01}));
  EXPECT_EQ(registers.writable.at(0x0100), 0);

  served = serve({0x10, 0x01, 0x00, 0x00, 0x02, 0x04, 0, 1, 0, 2}, rights);
  EXPECT_EQ(served.state, modbus::TransactionState::done);
  EXPECT_EQ(registers.writable.at(0x0101), 2);

  // Even a register the map does not have is 01 for a client that may not write it: it
  // learns nothing of the map.
  served = serve({0x06, 0x09, 0x99, 0x00, 0x05}, rights);
  EXPECT_EQ(out[1], 0x01);

  served = serve({0x04, 0x00, 0x11, 0x00, 0x01}, modbus::WriteRights::nothing());
  EXPECT_EQ(served.state, modbus::TransactionState::done);
  EXPECT_EQ((Bytes{out[2], out[3]}), (Bytes{0x12, 0x34}));
}

// A malformed write is still the malformed write's exception: the rights are asked only
// of a request that says which registers it writes.
TEST_F(RightsServing, AMalformedWriteKeepsItsOwnException) {
  serve({0x06, 0x01, 0x00, 0x00}, modbus::WriteRights::nothing());
  EXPECT_EQ(out[1], 0x03);
}

config::NetworkRange range(const std::string& text) {
  auto parsed = config::parse_network_range(text);
  if (auto* error = std::get_if<std::string>(&parsed)) ADD_FAILURE() << text << ": " << *error;
  return std::get<config::NetworkRange>(parsed);
}

config::PeerAddress address(const std::string& text) {
  config::PeerAddress a{};
  EXPECT_TRUE(config::parse_peer_address(text, a)) << text;
  return a;
}

TEST(PeerAllowList, Ipv4AndIpv6RangesAndSingleAddresses) {
  config::PeerAllowList list;
  list.ranges = {range("192.168.10.0/24"), range("127.0.0.1"), range("fd00::/8")};
  EXPECT_TRUE(list.allows(address("192.168.10.0")));
  EXPECT_TRUE(list.allows(address("192.168.10.255")));
  EXPECT_FALSE(list.allows(address("192.168.11.1")));
  EXPECT_TRUE(list.allows(address("127.0.0.1")));
  EXPECT_FALSE(list.allows(address("127.0.0.2")));
  EXPECT_TRUE(list.allows(address("fd12:3456::1")));
  EXPECT_FALSE(list.allows(address("fe80::1")));
  EXPECT_FALSE(list.allows(address("::1")));
  // What a dual-stack listener on :: sees of an IPv4 client.
  EXPECT_TRUE(list.allows(address("::ffff:192.168.10.7")));
  EXPECT_TRUE(config::PeerAllowList{}.allows(address("10.0.0.1")));  // no list: anyone

  config::PeerAllowList odd;
  odd.ranges = {range("10.0.0.0/9"), range("0.0.0.0/0")};
  EXPECT_TRUE(odd.ranges[0].contains(address("10.127.255.255")));
  EXPECT_FALSE(odd.ranges[0].contains(address("10.128.0.0")));
  EXPECT_TRUE(odd.ranges[1].contains(address("8.8.8.8")));
  EXPECT_FALSE(odd.ranges[1].contains(address("2001:db8::1")));  // IPv4's /0 is every IPv4 address only
}

TEST(PeerAllowList, WhatIsNoRangeSaysWhy) {
  const auto error = [](const std::string& text) {
    auto parsed = config::parse_network_range(text);
    return std::holds_alternative<std::string>(parsed) ? std::get<std::string>(parsed) : std::string("accepted");
  };
  EXPECT_NE(error("plant-scada").find("is not an IP address"), std::string::npos);
  EXPECT_NE(error("10.0.0.0/33").find("0..32"), std::string::npos);
  EXPECT_NE(error("fd00::/129").find("0..128"), std::string::npos);
  EXPECT_NE(error("10.0.0.0/").find("prefix length"), std::string::npos);
  EXPECT_NE(error("10.0.0.0/8x").find("prefix length"), std::string::npos);
  EXPECT_NE(error("192.168.10.7/24").find("host bits"), std::string::npos);
}

}  // namespace
}  // namespace unima
