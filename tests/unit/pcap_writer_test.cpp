// The pcap file of `unima-bridge monitor --pcap` (SPEC §20), byte for byte: the global
// header, an exported-PDU record with its tags (Wireshark's epan/exported_pdu.h), IPv6.

#include <gtest/gtest.h>

#include <vector>

#include "monitor/pcap_writer.hpp"

namespace unima::monitor {
namespace {

using Bytes = std::vector<std::uint8_t>;
using namespace std::chrono;

Bytes bytes_of(const std::string& text) { return Bytes(text.begin(), text.end()); }

// 2026-11-22T14:41:23.123456Z: 1795358483 s (0x6B02FF13), 123456 µs (0x0001E240).
const system_clock::time_point at =
    sys_days(year(2026) / November / 22) + hours(14) + minutes(41) + seconds(23) + microseconds(123456);
// Seed 004 §5.1: a TCP read of two input registers from 0x0011.
const Bytes tcp_query = {0x12, 0x34, 0x00, 0x00, 0x00, 0x06, 0x01, 0x04, 0x00, 0x11, 0x00, 0x02};

TEST(PcapWriter, TheGlobalHeaderIsClassicPcapWithMicrosecondsAndLinkType252) {
  std::string out;
  append_pcap_header(out);
  EXPECT_EQ(bytes_of(out), (Bytes{0xD4, 0xC3, 0xB2, 0xA1,   // magic, little endian: µs
                                  0x02, 0x00, 0x04, 0x00,   // version 2.4
                                  0x00, 0x00, 0x00, 0x00,   // UTC
                                  0x00, 0x00, 0x00, 0x00,   // accuracy
                                  0x00, 0x00, 0x04, 0x00,   // snapshot length 262144
                                  0xFC, 0x00, 0x00, 0x00}));  // LINKTYPE_WIRESHARK_UPPER_PDU
}

TEST(PcapWriter, ARecordIsTheTimeTheLengthsTheTagsAndTheFrame) {
  std::string out;
  append_pcap_record(out, {at, "mbtcp", IpEndpoint::v4({127, 0, 0, 1}, 40000), IpEndpoint::v4({0, 0, 0, 1}, 502),
                           tcp_query});
  Bytes expected = {
      0x13, 0xFF, 0x02, 0x6B,                                // seconds
      0x40, 0xE2, 0x01, 0x00,                                // microseconds
      0x44, 0x00, 0x00, 0x00,                                // captured: 56 bytes of tags + 12
      0x44, 0x00, 0x00, 0x00,                                // on the wire
      0x00, 0x0C, 0x00, 0x08, 'm', 'b', 't', 'c', 'p', 0, 0, 0,  // dissector, NUL-padded, padding counted
      0x00, 0x14, 0x00, 0x04, 127, 0, 0, 1,                  // IPv4 source
      0x00, 0x15, 0x00, 0x04, 0, 0, 0, 1,                    // IPv4 destination
      0x00, 0x18, 0x00, 0x04, 0, 0, 0, 2,                    // port type TCP
      0x00, 0x19, 0x00, 0x04, 0, 0, 0x9C, 0x40,              // source port 40000
      0x00, 0x1A, 0x00, 0x04, 0, 0, 0x01, 0xF6,              // destination port 502
      0x00, 0x00, 0x00, 0x00,                                // end of options
  };
  expected.insert(expected.end(), tcp_query.begin(), tcp_query.end());
  EXPECT_EQ(bytes_of(out), expected);
}

TEST(PcapWriter, IPv6EndpointsTakeTheIPv6TagsAndRecordsFollowEachOther) {
  const auto client = IpEndpoint::parse("::1", 5020);
  ASSERT_TRUE(client);
  EXPECT_TRUE(client->ipv6);
  std::string out;
  append_pcap_record(out, {at, "mbtcp", IpEndpoint::v4({10, 0, 0, 7}, 1), IpEndpoint::v4({0, 0, 0, 1}, 502), {}});
  const auto first = out.size();
  EXPECT_EQ(first, 16u + 56u);  // an empty frame: the tags only
  append_pcap_record(out, {at, "mbrtu", *client, *client, Bytes{0x01}});
  const auto record = bytes_of(out.substr(first));
  ASSERT_EQ(record.size(), 16u + 12u + 2 * 20u + 3 * 8u + 4u + 1u);
  EXPECT_EQ(record[8], record.size() - 16);
  EXPECT_EQ((Bytes(record.begin() + 16, record.begin() + 24)), (Bytes{0x00, 0x0C, 0x00, 0x08, 'm', 'b', 'r', 't'}));
  const Bytes loopback6 = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
  EXPECT_EQ((Bytes(record.begin() + 28, record.begin() + 32)), (Bytes{0x00, 0x16, 0x00, 0x10}));  // IPv6 source
  EXPECT_EQ((Bytes(record.begin() + 32, record.begin() + 48)), loopback6);
  EXPECT_EQ((Bytes(record.begin() + 48, record.begin() + 52)), (Bytes{0x00, 0x17, 0x00, 0x10}));  // IPv6 destination
  EXPECT_EQ(record.back(), 0x01);
}

TEST(PcapWriter, OnlyAddressesParse) {
  EXPECT_FALSE(IpEndpoint::parse("?", 0));
  EXPECT_FALSE(IpEndpoint::parse("", 0));
  EXPECT_FALSE(IpEndpoint::parse("10.0.0", 0));
  const auto v4 = IpEndpoint::parse("192.0.2.7", 1);
  ASSERT_TRUE(v4);
  EXPECT_FALSE(v4->ipv6);
  EXPECT_EQ((Bytes(v4->address.begin(), v4->address.begin() + 4)), (Bytes{192, 0, 2, 7}));
}

TEST(PcapWriter, ATimeBefore1970IsWrittenAs1970) {
  std::string out;
  append_pcap_record(out, {system_clock::time_point(-seconds(5)), "mbrtu", {}, {}, {}});
  EXPECT_EQ((bytes_of(out.substr(0, 8))), (Bytes(8, 0)));
}

}  // namespace
}  // namespace unima::monitor
