// Monitor lines as Wireshark's exported PDUs (SPEC §20): a query and its response are two
// records in opposite directions, RTU frames with their CRC for mbrtu, MBAP frames for
// mbtcp, bad frames as they were seen; the frames rebuilt from a line are the wire's.

#include <gtest/gtest.h>

#include <vector>

#include "modbus/adu_view.hpp"
#include "monitor/monitor_line.hpp"
#include "monitor/pcap_export.hpp"
#include "tests/support/seed_frames.hpp"

namespace unima::monitor {
namespace {

using Bytes = std::vector<std::uint8_t>;

// What a reader of the pcap sees of one record (read here independently of the writer).
struct Record {
  std::uint32_t seconds = 0, micros = 0;
  std::string dissector;
  Bytes source, destination;
  std::uint32_t source_port = 0, destination_port = 0;
  Bytes frame;
};

std::uint32_t le32(const std::string& s, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = v << 8 | static_cast<std::uint8_t>(s[at + static_cast<std::size_t>(i)]);
  return v;
}
std::uint32_t be(const std::string& s, std::size_t at, std::size_t size) {
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < size; ++i) v = v << 8 | static_cast<std::uint8_t>(s[at + i]);
  return v;
}

std::vector<Record> records(const std::string& pcap) {
  std::vector<Record> out;
  std::size_t at = 0;
  while (at + 16 <= pcap.size()) {
    Record r;
    r.seconds = le32(pcap, at);
    r.micros = le32(pcap, at + 4);
    const auto length = le32(pcap, at + 8);
    EXPECT_EQ(length, le32(pcap, at + 12));
    const auto end = at + 16 + length;
    std::size_t p = at + 16;
    while (true) {
      const auto tag = be(pcap, p, 2), size = be(pcap, p + 2, 2);
      p += 4;
      const auto value = pcap.substr(p, size);
      p += size;
      if (tag == 0) break;
      if (tag == 12) r.dissector = value.substr(0, value.find('\0'));
      if (tag == 20 || tag == 22) r.source.assign(value.begin(), value.end());
      if (tag == 21 || tag == 23) r.destination.assign(value.begin(), value.end());
      if (tag == 25) r.source_port = be(value, 0, 4);
      if (tag == 26) r.destination_port = be(value, 0, 4);
    }
    r.frame.assign(pcap.begin() + static_cast<std::ptrdiff_t>(p), pcap.begin() + static_cast<std::ptrdiff_t>(end));
    out.push_back(r);
    at = end;
  }
  EXPECT_EQ(at, pcap.size());
  return out;
}

std::vector<Record> export_line(const std::string& text) {
  const auto line = parse_monitor_line(text);
  EXPECT_TRUE(line) << text;
  std::string out;
  if (line) append_pcap_records(out, *line);
  return records(out);
}

const std::string stamp = "2026-11-22T14:41:23.123456Z";

TEST(PcapExport, ATcpQueryAndItsResponseAreTwoRecordsClientToServerPort502AndBack) {
  const auto r = export_line(stamp +
                             " tcp:127.0.0.1:40000 Ix=7 Rc=12 State=Done TrID=1234 PtID=0000 Len=0006 Ad=1 "
                             "PDU=04 00 11 00 02 Response=12 34 00 00 00 07 01 04 04 00 50 7F FF");
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].dissector, "mbtcp");
  EXPECT_EQ(r[0].seconds, 1795358483u);
  EXPECT_EQ(r[0].micros, 123456u);
  EXPECT_EQ(r[0].source, (Bytes{127, 0, 0, 1}));
  EXPECT_EQ(r[0].source_port, 40000u);
  EXPECT_EQ(r[0].destination, (Bytes{0, 0, 0, 1}));  // the unit addressed
  EXPECT_EQ(r[0].destination_port, 502u);
  EXPECT_EQ(r[0].frame, (Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x06, 0x01, 0x04, 0x00, 0x11, 0x00, 0x02}));
  EXPECT_EQ(r[1].dissector, "mbtcp");
  EXPECT_EQ(r[1].source, r[0].destination);
  EXPECT_EQ(r[1].source_port, 502u);
  EXPECT_EQ(r[1].destination, r[0].source);
  EXPECT_EQ(r[1].destination_port, 40000u);
  EXPECT_EQ(r[1].seconds, r[0].seconds);
  EXPECT_EQ(r[1].frame,
            (Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x07, 0x01, 0x04, 0x04, 0x00, 0x50, 0x7F, 0xFF}));
}

TEST(PcapExport, JsonLinesExportTheSame) {
  const auto r = export_line(R"({"time":")" + stamp +
                             R"(","port":"tcp:127.0.0.1:40000","ix":7,"rc":12,"state":"Done","trid":4660,"ptid":0,)"
                             R"("len":6,"ad":1,"pdu":"04 00 11 00 02","response":null})");
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].frame, (Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x06, 0x01, 0x04, 0x00, 0x11, 0x00, 0x02}));
}

TEST(PcapExport, ABadLengthIsExportedAsSeenAndAFrameShorterThanItsHeaderOnlyByItsResponse) {
  const auto bad_length =
      export_line(stamp + " tcp:127.0.0.1:40000 Ix=7 Rc=7 State=Err03 TrID=0005 PtID=0000 Len=0001 Ad=1 PDU=- Response=-");
  ASSERT_EQ(bad_length.size(), 1u);
  EXPECT_EQ(bad_length[0].frame, (Bytes{0x00, 0x05, 0x00, 0x00, 0x00, 0x01, 0x01}));
  const auto short_frame =
      export_line(stamp + " tcp:127.0.0.1:40000 Ix=7 Rc=3 State=Err03 Ad=- PDU=- Response=00 01 00 00 00 03 00 84 03");
  ASSERT_EQ(short_frame.size(), 1u);
  EXPECT_EQ(short_frame[0].dissector, "mbtcp");
  EXPECT_EQ(short_frame[0].source_port, 502u);
}

TEST(PcapExport, RtuFramesKeepTheirCrcABadOneIncludedAndTheLinesMasterIsTheClient) {
  const auto r = export_line(stamp + " rtu Ix=1 Rc=8 State=Not4Me Ad=1 PDU=04 00 11 00 02 CRC=21CE "
                                     "Response=01 04 04 00 50 7F FF 9B E5");
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].dissector, "mbrtu");
  EXPECT_EQ(r[0].frame, test_support::seed::read_query);
  EXPECT_EQ(r[0].source, (Bytes{0, 0, 0, 0}));
  EXPECT_EQ(r[0].source_port, 0u);
  EXPECT_EQ(r[0].destination, (Bytes{0, 0, 0, 1}));
  EXPECT_EQ(r[0].destination_port, 502u);
  EXPECT_EQ(r[1].frame, test_support::seed::read_response);
  EXPECT_EQ(r[1].source_port, 502u);

  const auto bad_crc = export_line(stamp + " rtu Ix=2 Rc=8 State=Err03 Ad=1 PDU=06 01 01 09 29 CRC=1E79 Response=-");
  ASSERT_EQ(bad_crc.size(), 1u);
  EXPECT_EQ(bad_crc[0].frame, (Bytes{0x01, 0x06, 0x01, 0x01, 0x09, 0x29, 0x1E, 0x79}));
}

TEST(PcapExport, WhoIsTheClientOnEachPort) {
  const auto client = [](const std::string& port, const std::string& mbap) {
    const auto line = parse_monitor_line(stamp + " " + port + " Ix=1 Rc=8 State=Done " + mbap +
                                         "Ad=5 PDU=03 00 00 00 01 Response=-");
    EXPECT_TRUE(line) << port;
    return line ? pcap_conversation(*line) : std::nullopt;
  };
  const std::string header = "TrID=0001 PtID=0000 Len=0006 ";
  const auto tls = client("tls:operator@192.0.2.9:5000", header);
  ASSERT_TRUE(tls);
  EXPECT_EQ(tls->dissector, "mbtcp");
  EXPECT_EQ(tls->client.address[0], 192);
  EXPECT_EQ(tls->client.port, 5000);
  EXPECT_EQ(tls->server.address[3], 5);
  const auto v6 = client("tcp:::1:5020", header);
  ASSERT_TRUE(v6);
  EXPECT_TRUE(v6->client.ipv6);
  EXPECT_EQ(v6->client.address[15], 1);
  EXPECT_EQ(v6->client.port, 5020);
  EXPECT_TRUE(v6->server.ipv6);
  EXPECT_EQ(v6->server.address[15], 5);
  const auto gateway = client("gw:10.0.0.5:40123", "");
  ASSERT_TRUE(gateway);
  EXPECT_EQ(gateway->dissector, "mbrtu");
  EXPECT_EQ(gateway->client.address[0], 10);
  EXPECT_EQ(gateway->client.port, 40123);
  const auto master_line = client("master", "");
  ASSERT_TRUE(master_line);
  EXPECT_EQ(master_line->dissector, "mbrtu");
  EXPECT_EQ(master_line->client.port, 0);
  const auto master_tcp = client("master", header);
  ASSERT_TRUE(master_tcp);
  EXPECT_EQ(master_tcp->dissector, "mbtcp");
  const auto unknown_peer = client("tcp:?", header);
  ASSERT_TRUE(unknown_peer);
  EXPECT_EQ(unknown_peer->client.port, 0);
  EXPECT_FALSE(unknown_peer->client.ipv6);
}

TEST(PcapExport, NoRecordsForACachedAnswerOrADropNotice) {
  EXPECT_TRUE(export_line(stamp + " gw:10.0.0.7:50211 Ix=13 Rc=8 State=Cached Ad=5 PDU=03 00 00 00 01 CRC=858E "
                                  "Response=05 03 02 12 34 44 F3")
                  .empty());
  EXPECT_TRUE(export_line(stamp + " monitor Dropped=12").empty());
}

// view_adu's inverse gives back every frame it was given, whole or cut short.
TEST(AduBytes, EveryFrameComesBackFromItsView) {
  const Bytes tcp = {0x12, 0x34, 0x00, 0x00, 0x00, 0x06, 0x01, 0x04, 0x00, 0x11, 0x00, 0x02};
  for (std::size_t size = 0; size <= tcp.size(); ++size) {
    const Bytes frame(tcp.begin(), tcp.begin() + static_cast<std::ptrdiff_t>(size));
    const auto back = modbus::adu_bytes(modbus::view_adu(frame, modbus::Framing::tcp));
    EXPECT_EQ(back, size < 7 ? Bytes{} : frame) << size;
  }
  const auto& rtu = test_support::seed::read_response;
  for (std::size_t size = 0; size <= rtu.size(); ++size) {
    const Bytes frame(rtu.begin(), rtu.begin() + static_cast<std::ptrdiff_t>(size));
    EXPECT_EQ(modbus::adu_bytes(modbus::view_adu(frame, modbus::Framing::rtu)), frame) << size;
  }
}

}  // namespace
}  // namespace unima::monitor
