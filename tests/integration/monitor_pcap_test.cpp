// The monitor log in Wireshark (SPEC §20): the real daemon logs a libmodbus client's
// traffic (and a foreign master's on the RTU line), `unima-bridge monitor --pcap` turns the
// log into a pcap file, and tshark, an independent reader, dissects it with no set-up —
// function codes, register values, exception codes, directions, a bad CRC.

#include <sstream>

#include "tests/integration/bridge_fixture.hpp"
#include "tests/integration/cli_under_test.hpp"
#include "tests/integration/rtu_fixture.hpp"
#include "tests/support/peers/cli_process.hpp"

namespace unima::test {
namespace {

using test_support::CliProcess;
using test_support::write_file;

// tshark's fields of each record, one line a record, tab separated. Its standard error
// (a warning when run as root) stays out of the lines.
std::vector<std::string> tshark_lines(const std::filesystem::path& pcap, const std::string& options) {
  const auto r = run("(tshark -r " + pcap.string() + " " + options + " 2>/dev/null)");  // run adds 2>&1
  EXPECT_EQ(r.status, 0) << "tshark: " << r.output;
  std::vector<std::string> lines;
  std::istringstream in(r.output);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<std::string> last(const std::vector<std::string>& lines, std::size_t n) {
  return {lines.end() - static_cast<std::ptrdiff_t>(std::min(n, lines.size())), lines.end()};
}

// Which side sent it (the exported PDU's source port), function, first register, registers
// read, the value of a write, the exception.
const std::string modbus_fields =
    "-T fields -e exported_pdu.src_port -e modbus.func_code -e modbus.reference_num -e modbus.regval_uint16 "
    "-e modbus.data -e modbus.exception_code";

class MonitorPcap : public BridgeTest {
 protected:
  void SetUp() override {
    BridgeTest::SetUp();
    log = dir.path() / "monitor.log";
    config.monitor_section = "monitor:\n  file: " + log.string() + "\n";
  }
  /// The transactions' lines are in the log once the last of them, a read of D2, is.
  bool logged_through_the_exception() const {
    return eventually([&] { return read_file(log).find("State=Err02") != std::string::npos; });
  }
  std::filesystem::path log;
};

// A read (D1's first two registers, the seed's example), a write, and a read of a bank
// that is not configured (exception 02): six records, query then response, in log order.
TEST_F(MonitorPcap, WiresharkShowsATcpClientsReadWriteAndException) {
  start();
  auto feed = feed_client();
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":0,"values":[80]})", 0x0011, 0x0050);
  {
    ModbusClient client(config.modbus_port);
    ASSERT_EQ(client.read_input(0x0011, 2), (std::vector<std::uint16_t>{0x0050, 0x7FFF}));
    ASSERT_TRUE(client.write(0x0100, 0x0929));
    ASSERT_FALSE(client.read_input(0x1200, 1));
    ASSERT_EQ(client.last_error(), EMBXILADD);
  }
  ASSERT_TRUE(logged_through_the_exception()) << read_file(log);

  const auto pcap = dir.path() / "modbus.pcap";
  const auto converted = run(bridge_cli() + " monitor --pcap " + pcap.string() + " " + log.string());
  ASSERT_EQ(converted.status, 0) << converted.output;
  EXPECT_EQ(converted.output, "");  // the pcap went to the file, nothing to the terminal

  const auto lines = tshark_lines(pcap, modbus_fields);
  ASSERT_GE(lines.size(), 6u) << read_file(log);
  // A client's source port is its own, not 502; the server's is 502.
  std::vector<std::string> seen;
  for (const auto& line : last(lines, 6)) {
    const auto tab = line.find('\t');
    const bool from_server = line.substr(0, tab) == "502";
    seen.push_back((from_server ? "server\t" : "client\t") + line.substr(tab + 1));
  }
  EXPECT_EQ(seen, (std::vector<std::string>{
                      "client\t4\t17\t\t\t",         // read input registers from 0x0011
                      "server\t4\t\t80,32767\t\t",   // 0x0050, 0x7FFF
                      "client\t6\t256\t\t0929\t",    // write 0x0929 into 0x0100
                      "server\t6\t256\t\t0929\t",    // its echo
                      "client\t4\t4608\t\t\t",       // read 0x1200, D2: not configured
                      "server\t4\t\t\t\t2",          // exception 02, illegal data address
                  }))
      << read_file(log);

  // Modbus/TCP with its MBAP header: a response carries its query's transaction id, and
  // Wireshark pairs the read's response with the record of its query.
  const auto pairs = last(tshark_lines(pcap, "-T fields -e frame.number -e _ws.col.Protocol -e mbtcp.trans_id "
                                             "-e modbus.request_frame"),
                          6);
  std::vector<std::vector<std::string>> fields;
  for (const auto& line : pairs) {
    std::vector<std::string> row;
    std::istringstream in(line);
    for (std::string field; std::getline(in, field, '\t');) row.push_back(field);
    row.resize(4);
    EXPECT_EQ(row[1], "Modbus/TCP") << line;
    fields.push_back(row);
  }
  for (std::size_t query = 0; query < fields.size(); query += 2) EXPECT_EQ(fields[query][2], fields[query + 1][2]);
  EXPECT_EQ(fields[1][3], fields[0][0]);  // the read's response names its query's frame
}

// --follow --pcap - streams: each record reaches the reader as the daemon logs it.
TEST_F(MonitorPcap, FollowStreamsRecordsToStandardOutput) {
  start();
  ASSERT_TRUE(eventually([&] { return std::filesystem::exists(log); }));
  const auto pcap = dir.path() / "live.pcap";
  CliProcess cli(pcap, {"monitor", "--follow", "--lines", "0", "--pcap", "-", log.string()});
  ASSERT_TRUE(eventually([&] {  // the global header, at once
    std::error_code missing;
    return std::filesystem::file_size(pcap, missing) == 24;
  })) << cli.output();
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.write(0x0100, 0x0929));
  // The CLI is still running: what it wrote so far is whole records.
  std::vector<std::string> lines;
  EXPECT_TRUE(eventually([&] {
    lines = tshark_lines(pcap, modbus_fields);
    return lines.size() == 2;
  })) << lines.size();
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_NE(lines[0].substr(0, lines[0].find('\t')), "502") << lines[0];  // the client's port
  EXPECT_TRUE(lines[0].ends_with("\t6\t256\t\t0929\t")) << lines[0];
  EXPECT_EQ(lines[1], "502\t6\t256\t\t0929\t");
}

TEST_F(MonitorPcap, PcapAndJsonExcludeEachOther) {
  write_file(log, "");
  const auto both = run(bridge_cli() + " monitor --json --pcap - " + log.string());
  EXPECT_EQ(both.status, 2);
  EXPECT_NE(both.output.find("--json and --pcap exclude each other"), std::string::npos) << both.output;
}

// The RTU line: a foreign master's query to slave 3 with slave 3's answer (Not4Me), a
// query to the bridge with a bad CRC (Err03, no answer), a read the bridge answers.
class MonitorPcapRtu : public RtuTest {};

TEST_F(MonitorPcapRtu, WiresharkShowsTheLinesFramesWithTheirCrcsABadOneFlagged) {
  const auto log = dir.path() / "monitor.log";
  config.monitor_section = "monitor:\n  file: " + log.string() + "\n";
  start_rtu();
  line->write(rtu_adu(3, {0x04, 0x02, 0x00, 0x00, 0x01}));
  line->write(rtu_adu(3, {0x04, 0x02, 0x01, 0x2C}));  // 300
  auto broken = rtu_adu(1, {0x04, 0x01, 0x00, 0x00, 0x01});
  broken.back() ^= 0x10;
  line->write(broken);
  expect_next_reply_is_to_a_read_of_w(0x7FFF);
  ASSERT_TRUE(eventually([&] { return read_file(log).find("State=Done") != std::string::npos; })) << read_file(log);

  const auto pcap = dir.path() / "rtu.pcap";
  const auto converted = run(bridge_cli() + " monitor --pcap " + pcap.string() + " " + log.string());
  ASSERT_EQ(converted.status, 0) << converted.output;
  // The one preference involved: Wireshark checks RTU CRCs only when asked to.
  const auto lines = tshark_lines(pcap, "-o mbrtu.crc_verification:TRUE -T fields -e exported_pdu.src_port "
                                        "-e mbrtu.unit_id -e modbus.func_code -e modbus.regval_uint16 "
                                        "-e mbrtu.crc16.status");
  EXPECT_EQ(lines, (std::vector<std::string>{
                       "0\t3\t4\t\t1",
                       "502\t3\t4\t300\t1",
                       "0\t1\t4\t\t0",
                       "0\t1\t4\t\t1",
                       "502\t1\t4\t32767\t1",
                   }))
      << read_file(log);
}

}  // namespace
}  // namespace unima::test
