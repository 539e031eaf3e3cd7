// Monitor lines (SPEC §5, seed 004 §8): every state gives the exact line, in text and JSON,
// with the seed's TCP and RTU frames; lines read back as they were written.

#include <gtest/gtest.h>

#include <vector>

#include "modbus/rtu/crc16.hpp"
#include "monitor/monitor_line.hpp"
#include "tests/support/seed_frames.hpp"

namespace unima::monitor {
using namespace unima::modbus;
namespace {

using Bytes = std::vector<std::uint8_t>;
using namespace std::chrono;

const system_clock::time_point line_time =
    sys_days(year(2026) / November / 22) + hours(14) + minutes(41) + seconds(23) + microseconds(123456);
const std::string line_stamp = "2026-11-22T14:41:23.123456Z";

std::string line(PortKind port, std::string_view peer, TransactionState state, const Bytes& query,
                 const Bytes& response, std::uint8_t ix = 7, MonitorFormat format = MonitorFormat::text) {
  const Transaction t{port, peer, line_time, state, query, response};
  std::string name;
  append_port_name(name, port, peer);
  std::string out;
  append_monitor_line(out, monitor_fields(t, ix, name), format);
  return out;
}

// Seed 004 §5.1: TCP read of two input registers from 0x0011, and its answer.
const Bytes monitor_tcp_query = {0x12, 0x34, 0x00, 0x00, 0x00, 0x06, 0x01, 0x04, 0x00, 0x11, 0x00, 0x02};
const Bytes tcp_response = {0x12, 0x34, 0x00, 0x00, 0x00, 0x07, 0x01, 0x04, 0x04, 0x00, 0x50, 0x7F, 0xFF};
// The same over RTU.
const Bytes rtu_query = test_support::seed::read_query;
const Bytes rtu_response = test_support::seed::read_response;

TEST(MonitorLine, SeedTcpReadIsDone) {
  EXPECT_EQ(line(PortKind::tcp, "127.0.0.1:40000", TransactionState::done, monitor_tcp_query, tcp_response),
            line_stamp +
                " tcp:127.0.0.1:40000 Ix=7 Rc=12 State=Done TrID=1234 PtID=0000 Len=0006 Ad=1 PDU=04 00 11 00 02 "
                "Response=12 34 00 00 00 07 01 04 04 00 50 7F FF\n");
}

TEST(MonitorLine, SeedRtuReadIsDoneWithItsCrc) {
  EXPECT_EQ(line(PortKind::rtu, "", TransactionState::done, rtu_query, rtu_response),
            line_stamp + " rtu Ix=7 Rc=8 State=Done Ad=1 PDU=04 00 11 00 02 CRC=21CE Response=01 04 04 00 50 7F FF 9B E5\n");
}

// SPEC §18: with several lines a line's ports carry its name; with one, today's names.
TEST(MonitorLine, PortNamesCarryTheLineWhenThereAreSeveral) {
  const auto port_name = [](PortKind port, std::string_view peer, std::string_view line_name) {
    std::string out;
    append_port_name(out, port, peer, line_name);
    return out;
  };
  EXPECT_EQ(port_name(PortKind::rtu, "", ""), "rtu");
  EXPECT_EQ(port_name(PortKind::rtu, "", "scada"), "rtu:scada");
  EXPECT_EQ(port_name(PortKind::master, "", ""), "master");
  EXPECT_EQ(port_name(PortKind::master, "", "field"), "master:field");
  EXPECT_EQ(port_name(PortKind::gateway, "10.0.0.5:40000", ""), "gw:10.0.0.5:40000");
  EXPECT_EQ(port_name(PortKind::gateway, "10.0.0.5:40000", "field"), "gw:field:10.0.0.5:40000");
}

TEST(MonitorLine, Not4MeShowsTheForeignResponseWhenHeard) {
  const Bytes query = {0x03, 0x04, 0x02, 0x02, 0x00, 0x01, 0x90, 0x50};
  const Bytes foreign = {0x03, 0x04, 0x02, 0x12, 0x34, 0xCD, 0x87};
  EXPECT_EQ(line(PortKind::rtu, "", TransactionState::not_for_me, query, foreign),
            line_stamp + " rtu Ix=7 Rc=8 State=Not4Me Ad=3 PDU=04 02 02 00 01 CRC=9050 Response=03 04 02 12 34 CD 87\n");
  EXPECT_EQ(line(PortKind::rtu, "", TransactionState::not_for_me, query, {}),
            line_stamp + " rtu Ix=7 Rc=8 State=Not4Me Ad=3 PDU=04 02 02 00 01 CRC=9050 Response=-\n");
}

TEST(MonitorLine, Not4MeOverTcpIsAnsweredGatewayTargetFailed) {
  const Bytes query = {0x00, 0x07, 0x00, 0x00, 0x00, 0x06, 0x07, 0x04, 0x00, 0x11, 0x00, 0x01};
  const Bytes answer = {0x00, 0x07, 0x00, 0x00, 0x00, 0x03, 0x07, 0x84, 0x0B};
  EXPECT_EQ(line(PortKind::tcp, "10.0.0.2:502", TransactionState::not_for_me, query, answer, 255),
            line_stamp +
                " tcp:10.0.0.2:502 Ix=255 Rc=12 State=Not4Me TrID=0007 PtID=0000 Len=0006 Ad=7 PDU=04 00 11 00 01 "
                "Response=00 07 00 00 00 03 07 84 0B\n");
}

TEST(MonitorLine, EachErrorState) {
  EXPECT_EQ(line(PortKind::rtu, "", TransactionState::err01, {0x01, 0x01, 0x00, 0x00, 0x00, 0x01, 0xFD, 0xCA},
                 {0x01, 0x81, 0x01, 0x81, 0x90}),
            line_stamp + " rtu Ix=7 Rc=8 State=Err01 Ad=1 PDU=01 00 00 00 01 CRC=FDCA Response=01 81 01 81 90\n");
  EXPECT_EQ(line(PortKind::rtu, "", TransactionState::err02, {0x01, 0x04, 0x00, 0x50, 0x00, 0x02, 0x71, 0xDA},
                 {0x01, 0x84, 0x02, 0xC2, 0xC1}),
            line_stamp + " rtu Ix=7 Rc=8 State=Err02 Ad=1 PDU=04 00 50 00 02 CRC=71DA Response=01 84 02 C2 C1\n");
  // Err03 also for a bad CRC: no answer, and the CRC as it came.
  EXPECT_EQ(line(PortKind::rtu, "", TransactionState::err03, {0x01, 0x04, 0x00, 0x11, 0x00, 0x02, 0x21, 0xCF}, {}),
            line_stamp + " rtu Ix=7 Rc=8 State=Err03 Ad=1 PDU=04 00 11 00 02 CRC=21CF Response=-\n");
  // Err04 also for a foreign response shorter than 5 bytes.
  EXPECT_EQ(line(PortKind::master, "", TransactionState::err04, {0x03, 0x04, 0x02, 0x02, 0x00, 0x01, 0x90, 0x50},
                 {0x03, 0x04, 0x02}),
            line_stamp + " master Ix=7 Rc=8 State=Err04 Ad=3 PDU=04 02 02 00 01 CRC=9050 Response=03 04 02\n");
}

TEST(MonitorLine, TimeoutOfAMasterPoll) {
  EXPECT_EQ(line(PortKind::master, "", TransactionState::timeout, {0x03, 0x06, 0x02, 0x02, 0x12, 0x34, 0x25, 0x27}, {}),
            line_stamp + " master Ix=7 Rc=8 State=Timeout Ad=3 PDU=06 02 02 12 34 CRC=2527 Response=-\n");
}

// SPEC §14: a TCP client's request forwarded on the master's RTU line, named by the client.
TEST(MonitorLine, AForwardedTransactionIsPortGwWithTheClientsAddress) {
  EXPECT_EQ(line(PortKind::gateway, "10.0.0.5:40123", TransactionState::timeout,
                 {0x03, 0x06, 0x02, 0x02, 0x12, 0x34, 0x25, 0x27}, {}),
            line_stamp + " gw:10.0.0.5:40123 Ix=7 Rc=8 State=Timeout Ad=3 PDU=06 02 02 12 34 CRC=2527 Response=-\n");
}

TEST(MonitorLine, AMasterWithATcpTargetSpeaksMbap) {
  EXPECT_EQ(line(PortKind::master, "192.168.1.9:502", TransactionState::done, monitor_tcp_query, tcp_response),
            line_stamp +
                " master Ix=7 Rc=12 State=Done TrID=1234 PtID=0000 Len=0006 Ad=1 PDU=04 00 11 00 02 "
                "Response=12 34 00 00 00 07 01 04 04 00 50 7F FF\n");
}

TEST(MonitorLine, ATooShortFrameShowsWhatItHas) {
  EXPECT_EQ(line(PortKind::tcp, "127.0.0.1:1", TransactionState::err03, {0x12, 0x34, 0x00}, {}),
            line_stamp + " tcp:127.0.0.1:1 Ix=7 Rc=3 State=Err03 Ad=- PDU=- Response=-\n");
  EXPECT_EQ(line(PortKind::rtu, "", TransactionState::err03, {0x01}, {}),
            line_stamp + " rtu Ix=7 Rc=1 State=Err03 Ad=1 PDU=- Response=-\n");
}

TEST(MonitorLine, JsonCarriesTheSameFields) {
  EXPECT_EQ(line(PortKind::tcp, "127.0.0.1:40000", TransactionState::done, monitor_tcp_query, tcp_response, 7,
                 MonitorFormat::json),
            R"({"time":")" + line_stamp +
                R"(","port":"tcp:127.0.0.1:40000","ix":7,"rc":12,"state":"Done","trid":4660,"ptid":0,"len":6,)"
                R"("ad":1,"pdu":"04 00 11 00 02","response":"12 34 00 00 00 07 01 04 04 00 50 7F FF"})"
                "\n");
  EXPECT_EQ(line(PortKind::rtu, "", TransactionState::err03, {0x01, 0x04, 0x00, 0x11, 0x00, 0x02, 0x21, 0xCF}, {}, 0,
                 MonitorFormat::json),
            R"({"time":")" + line_stamp +
                R"(","port":"rtu","ix":0,"rc":8,"state":"Err03","ad":1,"pdu":"04 00 11 00 02","crc":"21CF",)"
                R"("response":null})"
                "\n");
}

TEST(MonitorLine, DropNotice) {
  std::string text, json;
  append_drop_notice(text, line_time, 42, MonitorFormat::text);
  append_drop_notice(json, line_time, 42, MonitorFormat::json);
  EXPECT_EQ(text, line_stamp + " monitor Dropped=42\n");
  EXPECT_EQ(json, R"({"time":")" + line_stamp + R"(","port":"monitor","dropped":42})" "\n");
  for (const auto& l : {text, json}) {
    const auto parsed = parse_monitor_line(l);
    ASSERT_TRUE(parsed) << l;
    EXPECT_EQ(parsed->kind, MonitorLine::Kind::drop_notice);
    EXPECT_EQ(parsed->dropped, 42u);
    EXPECT_EQ(parsed->time, line_time);
  }
}

TEST(MonitorLine, EveryStateHasItsName) {
  const std::vector<std::string> names = {"Done", "Not4Me", "Err01", "Err02", "Err03", "Err04", "Timeout", "Cached"};
  for (std::size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(state_name(static_cast<TransactionState>(i)), names[i]);
    EXPECT_EQ(parse_state(names[i]), static_cast<TransactionState>(i));
  }
  EXPECT_FALSE(parse_state("done"));
}

// Written, read back, written again: the same line, in both formats and across them.
TEST(MonitorLine, LinesReadBackAsWritten) {
  struct Case {
    PortKind port;
    std::string peer;
    TransactionState state;
    Bytes query, response;
  };
  const std::vector<Case> cases = {
      {PortKind::tcp, "127.0.0.1:40000", TransactionState::done, monitor_tcp_query, tcp_response},
      {PortKind::rtu, "", TransactionState::done, rtu_query, rtu_response},
      {PortKind::rtu, "", TransactionState::err03, {0x01}, {}},
      {PortKind::tcp, "[::1]:5", TransactionState::err03, {0x12, 0x34, 0x00}, {}},
      {PortKind::master, "", TransactionState::timeout, {0x03, 0x06, 0x02, 0x02, 0x12, 0x34, 0x25, 0x27}, {}},
  };
  for (const auto& c : cases) {
    for (const auto format : {MonitorFormat::text, MonitorFormat::json}) {
      const auto written = line(c.port, c.peer, c.state, c.query, c.response, 200, format);
      const auto parsed = parse_monitor_line(written);
      ASSERT_TRUE(parsed) << written;
      EXPECT_EQ(parsed->kind, MonitorLine::Kind::transaction);
      EXPECT_EQ(parsed->time, line_time);
      EXPECT_EQ(parsed->ix, 200);
      EXPECT_EQ(parsed->rc, c.query.size());
      std::string again, other;
      append_monitor_line(again, parsed->fields(), format);
      EXPECT_EQ(again, written);
      const auto other_format = format == MonitorFormat::text ? MonitorFormat::json : MonitorFormat::text;
      append_monitor_line(other, parsed->fields(), other_format);
      EXPECT_EQ(other, line(c.port, c.peer, c.state, c.query, c.response, 200, other_format));
    }
  }
}

TEST(MonitorLine, OtherTextIsNotAMonitorLine) {
  for (const std::string& bad : std::vector<std::string>{"", "hello", "2026-11-22T14:41:23Z rtu Ix=1",
                                line_stamp + " rtu Ix=7 Rc=8 State=Fine Ad=1 PDU=04 Response=-",
                                line_stamp + " rtu Ix=300 Rc=8 State=Done Ad=1 PDU=04 Response=-",
                                line_stamp + " rtu Ix=1 Rc=8 State=Done Ad=1 PDU=4 Response=-",
                                line_stamp + " rtu Ix=1 Rc=8 State=Done Ad=1 PDU=04",
                                line_stamp + " rtu Ix=1 Rc=8 State=Done TrID=0001 Ad=1 PDU=04 Response=-",
                                std::string("{\"time\":\"x\"}"), std::string("{not json")})
    EXPECT_FALSE(parse_monitor_line(bad)) << bad;
}

// A JSON line is one value and nothing after it but white space; a NUL byte (what a crash
// can leave at the end of a log file) makes it no monitor line.
TEST(MonitorLine, AJsonLineWithAnythingAfterItIsNotAMonitorLine) {
  std::string json;
  append_drop_notice(json, line_time, 42, MonitorFormat::json);
  json.pop_back();  // its "\n"
  EXPECT_TRUE(parse_monitor_line(json + " \n"));
  for (const auto& after : {std::string(1, '\0'), std::string("\0garbage", 8), std::string(" x")})
    EXPECT_FALSE(parse_monitor_line(json + after)) << after.size();
}

// Every byte value reads as its two upper-case digits, spaced, in both formats.
TEST(MonitorLine, EveryByteValueIsWrittenInHex) {
  Bytes all(256);
  for (std::size_t b = 0; b < all.size(); ++b) all[b] = static_cast<std::uint8_t>(b);
  std::string expected;
  for (std::size_t b = 0; b < all.size(); ++b) {
    static constexpr char digits[] = "0123456789ABCDEF";
    if (b > 0) expected += ' ';
    expected += digits[b >> 4];
    expected += digits[b & 0x0F];
  }
  const auto text = line(PortKind::tcp, "127.0.0.1:40000", TransactionState::done, monitor_tcp_query, all);
  EXPECT_NE(text.find(" Response=" + expected + "\n"), std::string::npos) << text;
  const auto json = line(PortKind::tcp, "127.0.0.1:40000", TransactionState::done, monitor_tcp_query, all, 7,
                         MonitorFormat::json);
  EXPECT_NE(json.find("\"response\":\"" + expected + "\"}\n"), std::string::npos) << json;
}

// The monitor's writer formats into a raw buffer of monitor_line_bound() bytes: the same
// line as append_monitor_line, never past the bound, even for the longest frames and a
// peer name that JSON must escape at every character.
TEST(MonitorLine, WrittenIntoABufferItIsTheSameLineWithinItsBound) {
  Bytes longest_query(260), longest_response(260);
  for (std::size_t i = 0; i < 260; ++i) longest_query[i] = longest_response[i] = static_cast<std::uint8_t>(i * 7);
  const std::string peer(64, '\x01');
  for (const auto format : {MonitorFormat::text, MonitorFormat::json}) {
    const Transaction t{PortKind::tcp, peer, line_time, TransactionState::done, longest_query, longest_response};
    std::string name;
    append_port_name(name, PortKind::tcp, peer);
    const auto fields = monitor_fields(t, 255, name);
    std::string appended;
    append_monitor_line(appended, fields, format);
    const auto bound = monitor_line_bound(fields);
    std::string buffer(bound + 64, '#');
    const char* const begin = buffer.data();
    const char* const end = write_monitor_line(buffer.data(), fields, format);
    ASSERT_LE(end - begin, static_cast<std::ptrdiff_t>(bound));
    EXPECT_EQ(std::string(begin, end), appended);
    EXPECT_EQ(buffer.substr(bound), std::string(64, '#')) << "nothing written past the bound";
  }
}

TEST(MonitorLine, SeedFramesCarryValidCrcs) {
  for (const auto& frame : {rtu_query, rtu_response}) {
    const std::uint16_t wire = static_cast<std::uint16_t>(frame[frame.size() - 2] | frame[frame.size() - 1] << 8);
    EXPECT_EQ(crc16(std::span(frame).first(frame.size() - 2)), wire);
  }
}

}  // namespace
}  // namespace unima::monitor
