// The gateway end to end (SPEC §14, issue 31): the daemon in master mode polls simulated
// foreign slaves on a pty while Modbus TCP clients reach them through it, and Modbus/TCP
// Security clients (tests/integration/tls/modbus_tls_client.py) within their roles' rights.
// What a slave hears and says is checked in the simulator's frame log, byte for byte.

#include <fmt/format.h>
#include <modbus/modbus.h>

#include <sstream>
#include <string>
#include <thread>

#include "tests/integration/certificate_fixture.hpp"
#include "master/gateway_queue.hpp"
#include "tests/integration/gateway_fixture.hpp"

namespace unima::test {
namespace {

// Every function goes to the slave as the client sent it, and the slave's answer comes back
// as it said it, with the client's transaction id and unit id.
TEST_F(GatewayTest, EveryFunctionIsForwardedByteExactWithTheClientsTransactionId) {
  start_with("{ units: [5-7], timeout: 300ms }");
  ASSERT_EQ(sim->control("set 5 0 4660"), "ok");  // D0 = 0x1234
  const std::vector<Bytes> requests = {
      {0x03, 0x00, 0x00, 0x00, 0x02},                          // D0..D1
      {0x06, 0x00, 0x01, 0x00, 0x2A},                          // D1 = 42
      {0x10, 0x00, 0x02, 0x00, 0x02, 0x04, 0x00, 0x01, 0x00, 0x02},  // D2, D3
      {0x01, 0x00, 0x00, 0x00, 0x08},                          // M0..M7
      {0x02, 0xF8, 0x00, 0x00, 0x08},                          // X0..X7
      {0x05, 0x00, 0x03, 0xFF, 0x00},                          // M3 on
      {0x0F, 0x00, 0x08, 0x00, 0x0A, 0x02, 0xFF, 0x03},        // M8..M17
      {0x03, 0x00, 0x00, 0x00, 0x04},                          // D0..D3 as written
  };
  auto socket = Socket::tcp(config.modbus_port);
  for (std::size_t i = 0; i < requests.size(); ++i) {
    const auto transaction = static_cast<std::uint16_t>(0x4100 + i);
    const auto answer = ask(socket, transaction, plc, requests[i]);
    ASSERT_TRUE(answer) << "request " << i << "\n" << diagnostics();
    EXPECT_EQ(answer->transaction, transaction);
    EXPECT_EQ(answer->unit, plc);
    EXPECT_EQ(heard(rtu_frame(plc, requests[i])), 1u) << "request " << i << "\n" << diagnostics();
    EXPECT_TRUE(said(rtu_frame(plc, answer->pdu))) << "request " << i << ": " << hex(answer->pdu) << "\n" << diagnostics();
    EXPECT_EQ(answer->pdu[0], requests[i][0]) << "request " << i << ": " << hex(answer->pdu);
  }
  EXPECT_EQ(sim->control("get 5 1"), "value 42");
  EXPECT_EQ(sim->control("coil 5 3"), "coil 1");
  // The last read: what functions 3, 6 and 16 left in D0..D3.
  const auto last = ask(socket, 0x4200, plc, {0x03, 0x00, 0x00, 0x00, 0x04});
  ASSERT_TRUE(last);
  EXPECT_EQ(hex(last->pdu), "03 08 12 34 00 2A 00 01 00 02");
}

// A libmodbus client sees the foreign slave as if it were on its own line.
TEST_F(GatewayTest, ALibmodbusClientReadsAndWritesAForeignSlave) {
  start_with("{ units: [5-7], timeout: 300ms }");
  ASSERT_EQ(sim->control("set 5 10 777"), "ok");
  ModbusClient client(config.modbus_port, plc);
  ASSERT_TRUE(client.connected());
  EXPECT_EQ(client.read_holding(10, 1), std::optional(std::vector<std::uint16_t>{777}));
  EXPECT_TRUE(client.write(11, 1234));
  EXPECT_TRUE(client.write_many(12, {5, 6}));
  EXPECT_EQ(sim->control("get 5 11"), "value 1234");
  EXPECT_EQ(client.read_holding(11, 3), std::optional(std::vector<std::uint16_t>{1234, 5, 6}));
  // The bridge's own unit id still serves the banks: output 1 holds the stepper's poll.
  EXPECT_TRUE(output_becomes(1, 8)) << diagnostics();
}

// The slave's exception is its answer: passed back as it came. Function 4 is one the PLC lacks.
TEST_F(GatewayTest, TheSlavesExceptionIsPassedBack) {
  start_with("{ units: [5-7], timeout: 300ms }");
  auto socket = Socket::tcp(config.modbus_port);
  const auto no_function = ask(socket, 1, plc, {0x04, 0x00, 0x00, 0x00, 0x01});
  ASSERT_TRUE(no_function) << diagnostics();
  EXPECT_EQ(hex(no_function->pdu), "84 01");
  EXPECT_TRUE(said(rtu_frame(plc, {0x84, 0x01}))) << diagnostics();
  ModbusClient client(config.modbus_port, stepper);
  EXPECT_FALSE(client.read_holding(0x0500, 1));  // outside the stepper driver's map
  EXPECT_EQ(client.last_error(), EMBXILADD);
}

// SPEC §14: a unit id the gateway does not route is 0x0A; the bridge's own, 0 and 255 serve the banks.
TEST_F(GatewayTest, AUnitNotRoutedIsGatewayPathUnavailable) {
  start_with("{ units: [5-7], timeout: 300ms }");
  ModbusClient unrouted(config.modbus_port, 9);
  EXPECT_FALSE(unrouted.read_holding(0, 1));
  EXPECT_EQ(unrouted.last_error(), EMBXGPATH);
  for (const int unit : {1, 0, 255}) {
    ModbusClient own(config.modbus_port, unit);
    EXPECT_TRUE(own.read_input(c_bank, 1)) << "unit " << unit;
  }
  EXPECT_EQ(heard(rtu_frame(9, {0x03, 0x00, 0x00, 0x00, 0x01})), 0u);
}

// No answer within the time-out: 0x0B, and a write that got none is not sent again; nor is
// a read: the client decides whether to ask again.
TEST_F(GatewayTest, ADeadSlaveIsGatewayTargetFailedAndNothingIsRetried) {
  start_with("{ units: [5-7], timeout: 300ms }");
  auto socket = Socket::tcp(config.modbus_port);
  const Bytes write{0x05, 0x07, 0xD0, 0xFF, 0x00};  // ENABLE on the dead SIC184
  const auto started = std::chrono::steady_clock::now();
  const auto answer = ask(socket, 0x0777, dead, write);
  const auto took = std::chrono::steady_clock::now() - started;
  ASSERT_TRUE(answer) << diagnostics();
  EXPECT_EQ(answer->transaction, 0x0777);
  EXPECT_EQ(hex(answer->pdu), "85 0B");
  EXPECT_GE(took, 300ms);
  const Bytes read{0x03, 0x00, 0x00, 0x00, 0x01};
  const auto read_answer = ask(socket, 0x0778, dead, read);
  ASSERT_TRUE(read_answer);
  EXPECT_EQ(hex(read_answer->pdu), "83 0B");
  // A retry would go at the time-out's end, before the line's next turns: after two more
  // polls of the stepper driver (every 200 ms), each request has gone on the line once.
  const auto polled = polls();
  ASSERT_TRUE(eventually([&] { return polls() >= polled + 2; })) << diagnostics();
  EXPECT_EQ(heard(rtu_frame(dead, write)), 1u) << diagnostics();
  EXPECT_EQ(heard(rtu_frame(dead, read)), 1u) << diagnostics();
  // The gateway keeps serving the others.
  const auto alive = ask(socket, 0x0779, plc, read);
  ASSERT_TRUE(alive);
  EXPECT_EQ(alive->pdu[0], 0x03);
}

// Issue 43, finding 1: a slave that answers past the gateway's time-out (a busy PLC) must
// not have its late answer handed to the next request — another client's, or the bridge's
// own poll of the same slave. A's read of D0 times out (the PLC answers at 420 ms, the
// time-out is 300 ms); B's read of D1, asked at once, is answered with D1, and the poll of
// D200 reads D200, never D0's value.
TEST_F(GatewayTest, ALateAnswerIsNeverHandedToTheNextRequest) {
  simulate({"5=wecon-lx5v", "6=stepper-driver"});
  config.master = "retries: 0, response_timeout: 300ms";
  config.blocks = "  - { type: poll, device: 5, profile: wecon-lx5v, operand: D200, period: 250ms, output: 1 }\n";
  config.modbus_extra = "  gateway: { units: [5-6], timeout: 300ms, cache: 1s }\n";
  ASSERT_EQ(sim->control("set 5 0 4660"), "ok");   // D0 = 0x1234
  ASSERT_EQ(sim->control("set 5 1 22136"), "ok");  // D1 = 0x5678
  ASSERT_EQ(sim->control("set 5 200 99"), "ok");   // D200
  start();
  ASSERT_TRUE(output_becomes(1, 99)) << diagnostics();
  auto a = Socket::tcp(config.modbus_port);
  auto b = Socket::tcp(config.modbus_port);
  for (int round = 0; round < 3; ++round) {
    ASSERT_EQ(sim->control("slow 5 420"), "ok");
    const Bytes read_d0{0x03, 0x00, 0x00, 0x00, 0x01};
    const Bytes read_d1{0x03, 0x00, 0x01, 0x00, 0x01};
    const auto heard_before = heard(rtu_frame(plc, read_d0));
    a.send(Bytes{0x00, static_cast<std::uint8_t>(round), 0, 0, 0, 6, plc, 0x03, 0x00, 0x00, 0x00, 0x01});
    ASSERT_TRUE(eventually([&] { return heard(rtu_frame(plc, read_d0)) > heard_before; })) << diagnostics();
    ASSERT_EQ(sim->control("slow 5 0"), "ok");  // D0's answer still comes at 420 ms
    const auto answer_b = ask(b, static_cast<std::uint16_t>(0x0100 + round), plc, read_d1);
    const auto answer_a = a.receive(9);
    ASSERT_EQ(answer_a.size(), 9u) << diagnostics();
    EXPECT_EQ(hex(Bytes(answer_a.begin() + 7, answer_a.end())), "83 0B") << "A timed out";
    ASSERT_TRUE(answer_b) << diagnostics();
    EXPECT_EQ(hex(answer_b->pdu), "03 02 56 78") << "B got " << hex(answer_b->pdu) << "\n" << diagnostics();
    // Asked again within the cache's window: whatever is served is D1's value.
    const auto again = ask(b, static_cast<std::uint16_t>(0x0200 + round), plc, read_d1);
    ASSERT_TRUE(again) << diagnostics();
    EXPECT_EQ(hex(again->pdu), "03 02 56 78") << diagnostics();
  }
  // The poll of D200 read D200 all along: no answer to it carried D0's or D1's value.
  std::istringstream log(read_file(monitor_log()));
  std::size_t polls_of_d200 = 0;
  for (std::string line; std::getline(log, line);) {
    if (line.find("PDU=03 00 C8 00 01") == std::string::npos) continue;
    ++polls_of_d200;
    EXPECT_EQ(line.find("12 34"), std::string::npos) << line;
    EXPECT_EQ(line.find("56 78"), std::string::npos) << line;
  }
  EXPECT_GE(polls_of_d200, 2u);  // the first, which made output 1 read 99, and more during the rounds
}

// Forwarded requests and polls share the line: the poll keeps coming while a client asks
// without pause, and each forwarded transaction is a monitor line of port gw.
TEST_F(GatewayTest, PollsGoOnBesideAClientAndEachTransactionIsAMonitorLine) {
  start_with("{ units: [5-7], timeout: 300ms }");
  ASSERT_TRUE(output_becomes(1, 8)) << diagnostics();
  auto socket = Socket::tcp(config.modbus_port);
  const auto polls_before = polls();
  const auto started = std::chrono::steady_clock::now();
  std::size_t asked = 0;
  while (std::chrono::steady_clock::now() - started < 1500ms) {
    const auto answer = ask(socket, static_cast<std::uint16_t>(asked), plc, {0x03, 0x00, 0x00, 0x00, 0x01});
    ASSERT_TRUE(answer) << diagnostics();
    ASSERT_EQ(answer->pdu[0], 0x03);
    ++asked;
  }
  EXPECT_GE(asked, 10u);
  // 200 ms polls for 1.5 s: 7 or 8 on time; at least 5 even on a loaded machine.
  EXPECT_GE(polls() - polls_before, 5u) << diagnostics();
  (void)ask(socket, 0x0900, dead, {0x03, 0x00, 0x00, 0x00, 0x01});
  std::string log;
  ASSERT_TRUE(eventually([&] {
    log = read_file(monitor_log());
    return log.find("State=Timeout Ad=7") != std::string::npos;
  })) << log;
  const auto port = " gw:127.0.0.1:" + std::to_string(socket.local_port()) + " ";
  EXPECT_NE(log.find(port), std::string::npos) << log;
  EXPECT_NE(log.find(port + "Ix="), std::string::npos) << log;
  const auto done = log.find("State=Done Ad=5 PDU=03 00 00 00 01");
  ASSERT_NE(done, std::string::npos) << log;
  EXPECT_NE(log.rfind(" gw:127.0.0.1:", done), std::string::npos) << log;
  EXPECT_NE(log.find(" master "), std::string::npos) << log;  // the polls, as before
}

// A request that cannot start within `wait` is answered "busy": here the line is held by a
// request to a dead slave for its whole time-out.
TEST_F(GatewayTest, ARequestThatCannotStartWithinWaitIsBusy) {
  start_with("{ units: [5-7], timeout: 800ms, wait: 150ms }");
  auto first = Socket::tcp(config.modbus_port);
  auto second = Socket::tcp(config.modbus_port);
  const Bytes to_dead{0x03, 0x00, 0x00, 0x00, 0x01};
  // The first request holds the line; the second waits behind it.
  Bytes adu{0x00, 0x01, 0, 0, 0, 6, dead, 0x03, 0x00, 0x00, 0x00, 0x01};
  first.send(adu);
  ASSERT_TRUE(sim->wait_for_frame(hex(rtu_frame(dead, to_dead)))) << diagnostics();
  const auto started = std::chrono::steady_clock::now();
  const auto busy = ask(second, 0x0002, plc, {0x03, 0x00, 0x00, 0x00, 0x01});
  const auto took = std::chrono::steady_clock::now() - started;
  ASSERT_TRUE(busy) << diagnostics();
  EXPECT_EQ(busy->transaction, 0x0002);
  EXPECT_EQ(hex(busy->pdu), "83 06");
  EXPECT_LT(took, 700ms);  // at its wait, not when the line is free again
  EXPECT_EQ(heard(rtu_frame(plc, {0x03, 0x00, 0x00, 0x00, 0x01})), 0u);
  const auto header = first.receive(9);
  ASSERT_EQ(header.size(), 9u);
  EXPECT_EQ(header[7], 0x83);
  EXPECT_EQ(header[8], 0x0B);
}

// While the line is held, a normal client's request and then a priority peer's wait: the
// priority peer goes first when the line frees; then each client in turn.
TEST_F(GatewayTest, APriorityPeerGoesFirstAndClientsTakeTurns) {
  start_with("{ units: [5-7], timeout: 600ms, wait: 3s, priority: [127.0.0.2] }");
  auto holder = Socket::tcp(config.modbus_port);
  auto normal = Socket::tcp(config.modbus_port);
  auto other = Socket::tcp(config.modbus_port);
  auto priority = Socket::tcp_from("127.0.0.2", config.modbus_port);
  ASSERT_TRUE(priority.valid());
  const auto request = [](std::uint16_t transaction, std::uint8_t unit, std::uint16_t reg) {
    return Bytes{static_cast<std::uint8_t>(transaction >> 8), static_cast<std::uint8_t>(transaction), 0, 0, 0, 6,
                 unit, 0x03, static_cast<std::uint8_t>(reg >> 8), static_cast<std::uint8_t>(reg), 0x00, 0x01};
  };
  holder.send(request(1, dead, 0));
  ASSERT_TRUE(sim->wait_for_frame(hex(rtu_frame(dead, {0x03, 0x00, 0x00, 0x00, 0x01})))) << diagnostics();
  normal.send(request(2, plc, 2));
  normal.send(request(3, plc, 3));  // pipelined: waits behind its first
  other.send(request(4, plc, 4));
  // normal's first and other's wait in the queue (normal's second behind its first).
  ASSERT_TRUE(eventually([&] {
    const auto unit = unit_status(plc);
    return unit.is_object() && unit["queue_depth"] == 2;
  })) << status().dump(1);
  priority.send(request(5, plc, 5));
  for (auto* socket : {&normal, &normal, &other, &priority}) ASSERT_EQ(socket->receive(11).size(), 11u) << diagnostics();
  ASSERT_EQ(holder.receive(9).size(), 9u);
  // The order the PLC heard them in: the priority peer's, then one of each client, then the rest.
  std::vector<std::string> order;
  for (const auto& f : sim->frames())
    if (f.rx && f.hex.starts_with("05 03 00 0")) order.push_back(f.hex.substr(0, 14));
  EXPECT_EQ(order, (std::vector<std::string>{"05 03 00 05 00", "05 03 00 02 00", "05 03 00 04 00", "05 03 00 03 00"}))
      << diagnostics();
}

// Issue 43, finding 5: one host opening 100 connections left another client 3 answers in
// 10 s. Hosts take turns before their connections do, and a host has at most
// most_waiting_per_host requests waiting: the rest are answered busy at once.
TEST_F(GatewayTest, OneHostsManyConnectionsLeaveAnotherHostItsTurns) {
  start_with("{ units: [5-7], timeout: 2s, wait: 20s }");
  const Bytes flood_read{0x03, 0x00, 0x00, 0x00, 0x01};
  const Bytes own_read{0x03, 0x00, 0x09, 0x00, 0x01};
  // The dead slave holds the line for its time-out while the flood queues up.
  auto holder = Socket::tcp(config.modbus_port);
  holder.send(Bytes{0x00, 0x01, 0, 0, 0, 6, dead, 0x03, 0x00, 0x00, 0x00, 0x01});
  ASSERT_TRUE(sim->wait_for_frame(hex(rtu_frame(dead, {0x03, 0x00, 0x00, 0x00, 0x01})))) << diagnostics();
  std::vector<Socket> flood;
  for (int i = 0; i < 100; ++i) {
    flood.push_back(Socket::tcp(config.modbus_port));
    ASSERT_TRUE(flood.back().valid());
  }
  for (std::size_t i = 0; i < flood.size(); ++i) {
    Bytes adu{0x00, static_cast<std::uint8_t>(i), 0, 0, 0, 6, plc};
    adu.insert(adu.end(), flood_read.begin(), flood_read.end());
    flood[i].send(adu);
  }
  ASSERT_TRUE(eventually([&] {
    const auto unit = unit_status(plc);
    return unit.is_object() && unit["queue_depth"] == master::GatewayQueue::most_waiting_per_host;
  })) << status().dump(1);

  auto other = Socket::tcp_from("127.0.0.2", config.modbus_port);
  ASSERT_TRUE(other.valid());
  const auto flood_frame = hex(rtu_frame(plc, flood_read));
  const auto own_frame = hex(rtu_frame(plc, own_read));
  const auto heard_in_order = [&] {
    std::vector<bool> own;  // true: the other host's read, false: the flood's
    for (const auto& f : sim->frames())
      if (f.rx && (f.hex == flood_frame || f.hex == own_frame)) own.push_back(f.hex == own_frame);
    return own;
  };
  const auto flood_before = heard_in_order().size();
  for (std::uint16_t t = 1; t <= 3; ++t) {
    const auto answer = ask(other, t, plc, own_read, 5000ms);
    ASSERT_TRUE(answer) << diagnostics();
    EXPECT_EQ(answer->pdu.at(0), 0x03) << hex(answer->pdu);
  }
  // Each of its reads waited for at most the flood's transaction on the line and one turn.
  ASSERT_EQ(flood_before, 0u);
  const auto order = heard_in_order();
  std::size_t flood_until_third = 0, own_heard = 0;
  for (const bool own : order) {
    if (own && ++own_heard == 3) break;
    flood_until_third += !own;
  }
  EXPECT_EQ(own_heard, 3u);
  EXPECT_LE(flood_until_third, 4u) << diagnostics();

  // Every flood connection got an answer: the slave's, or busy (at once) past the bound.
  std::size_t busy = 0;
  for (auto& socket : flood) {
    const auto header = socket.receive(9, 10000ms);
    ASSERT_EQ(header.size(), 9u) << diagnostics();
    if (header[7] == 0x83) {
      EXPECT_EQ(header[8], 0x06);
      ++busy;
    } else {
      EXPECT_EQ(socket.receive(2, 1000ms).size(), 2u);
    }
  }
  EXPECT_EQ(busy, 100u - master::GatewayQueue::most_waiting_per_host);
  EXPECT_EQ(unit_status(plc)["busy"], busy) << status().dump(1);
}

// The TLS port (SPEC §14 with §11's roles): the gateway beside a Modbus/TCP Security port
// with the certificates of tests/integration/tls/make_certificates.sh.
class GatewayTlsTest : public GatewayTest {
 protected:
  void SetUp() override {
    GatewayTest::SetUp();
    certs = dir.path() / "certs";
    const auto made = run(tls_dir + "/make_certificates.sh " + certs.string());
    ASSERT_EQ(made.status, 0) << made.output;
    tls_port = free_port();
  }
  /// The operator may write W and unit 5, the viewer W only; `extra`: more keys of modbus.tls.
  void start_with_tls(const std::string& extra = "") {
    const auto pem = [&](const std::string& name) { return (certs / name).string(); };
    start_with("{ units: [5-7], timeout: 300ms }",
               "  tls: { listen: 127.0.0.1, port: " + std::to_string(tls_port) + ", certificate: " + pem("server.pem") +
                   ", key: " + pem("server.key") + ", ca: " + pem("ca.pem") +
                   ", roles: { operator: { write: [W, \"unit 5\"] }, viewer: { write: [W] } }" + extra + " }\n");
    ASSERT_TRUE(wait_for_port(tls_port)) << diagnostics();
  }
  /// What `identity` got for each of `requests` (PDUs in hex) sent to `unit` over TLS: the
  /// answers' PDUs in hex, or the client's "error: …" line.
  std::vector<std::string> tls_client(const std::string& identity, std::uint8_t unit,
                                      const std::vector<std::string>& requests) const {
    std::string command = tls_dir + "/modbus_tls_client.py --unit " + std::to_string(unit) + " " +
                          std::to_string(tls_port) + " " + (certs / "ca.pem").string() + " " +
                          (certs / (identity + ".pem")).string() + " " + (certs / (identity + ".key")).string() + " --";
    for (const auto& r : requests) command += " " + r;
    std::istringstream output(run(command).output);
    std::vector<std::string> answers;
    for (std::string line; std::getline(output, line);)
      if (!line.starts_with("server: ") && !line.starts_with("version: ")) answers.push_back(line);
    return answers;
  }

  std::filesystem::path certs;
  std::uint16_t tls_port = 0;
};

const Bytes write_d11{0x06, 0x00, 0x0B, 0x04, 0xD2};  // D11 = 1234 on the PLC

// Reads are forwarded for every role; a write only for a role whose list names the unit,
// else 01 and nothing goes on the line; a unit not routed is 0x0A over TLS too.
TEST_F(GatewayTlsTest, AWriteGoesToTheUnitTheRoleNamesAndReadsForEveryRole) {
  start_with_tls();
  ASSERT_EQ(sim->control("set 5 10 777"), "ok");
  EXPECT_EQ(tls_client("viewer", plc, {"03000a0001", "06000b04d2", "10000b00010204d2"}),
            (std::vector<std::string>{"03020309", "8601", "9001"}))
      << diagnostics();
  EXPECT_EQ(tls_client("norole", plc, {"03000a0001", "06000b04d2"}), (std::vector<std::string>{"03020309", "8601"}));
  EXPECT_EQ(heard(rtu_frame(plc, {0x03, 0x00, 0x0A, 0x00, 0x01})), 2u) << diagnostics();
  EXPECT_EQ(heard(rtu_frame(plc, write_d11)), 0u) << diagnostics();
  EXPECT_EQ(sim->control("get 5 11"), "value 0");

  EXPECT_EQ(tls_client("operator", plc, {"06000b04d2", "03000b0001"}),
            (std::vector<std::string>{"06000b04d2", "030204d2"}))
      << diagnostics();
  EXPECT_EQ(heard(rtu_frame(plc, write_d11)), 1u) << diagnostics();
  EXPECT_EQ(sim->control("get 5 11"), "value 1234");
  // Unit 6 is routed but not the operator's; unit 9 is not routed at all.
  EXPECT_EQ(tls_client("operator", stepper, {"0600000001"}), (std::vector<std::string>{"8601"}));
  EXPECT_EQ(tls_client("operator", 9, {"0300000001"}), (std::vector<std::string>{"830a"}));
}

// modbus.tls.read_only forwards no write, whatever the role; reads still go.
TEST_F(GatewayTlsTest, ReadOnlyForwardsNoWrite) {
  start_with_tls(", read_only: true");
  EXPECT_EQ(tls_client("operator", plc, {"06000b04d2", "03000b0001"}), (std::vector<std::string>{"8601", "03020000"}))
      << diagnostics();
  EXPECT_EQ(heard(rtu_frame(plc, write_d11)), 0u) << diagnostics();
}

// modbus.gateway.functions: read (issue 43, finding 9): the plain port forwards reads, and
// no write, restart (fn 8) or vendor function to the line, while it keeps writing the
// bridge's own banks.
TEST_F(GatewayTest, FunctionsReadForwardsReadsOnlyAndTheOwnBanksStayWritable) {
  start_with("{ units: [5-7], timeout: 300ms, functions: read }");
  ASSERT_EQ(sim->control("set 5 10 777"), "ok");
  auto socket = Socket::tcp(config.modbus_port);
  const auto read = ask(socket, 0x0101, plc, Bytes{0x03, 0x00, 0x0A, 0x00, 0x01});
  ASSERT_TRUE(read) << diagnostics();
  EXPECT_EQ(hex(read->pdu), "03 02 03 09");
  const Bytes restart{0x08, 0x00, 0x01, 0x00, 0x00};
  const Bytes vendor{0x41};
  for (const auto& refused : {write_d11, restart, vendor}) {
    const auto answer = ask(socket, 0x0102, plc, refused);
    ASSERT_TRUE(answer) << hex(refused) << diagnostics();
    EXPECT_EQ(hex(answer->pdu), fmt::format("{:02X} 01", refused[0] | 0x80)) << hex(refused) << " is refused with exception 01";
    EXPECT_EQ(heard(rtu_frame(plc, refused)), 0u) << hex(refused) << diagnostics();
  }
  ModbusClient client(config.modbus_port, 1);
  ASSERT_TRUE(client.connected());
  EXPECT_TRUE(client.write(0x3000, 17)) << "the bridge's own W stays writable" << diagnostics();
}

// The bridge-wide modbus.tcp.read_only holds on the TLS port and for the plain port's
// forwarded writes too.
TEST_F(GatewayTlsTest, TheBridgeWideReadOnlyForwardsNoWriteOnEitherPort) {
  config.tcp_extra = ", read_only: true";
  start_with_tls();
  EXPECT_EQ(tls_client("operator", plc, {"06000b04d2"}), (std::vector<std::string>{"8601"})) << diagnostics();
  auto socket = Socket::tcp(config.modbus_port);
  const auto answer = ask(socket, 0x0101, plc, write_d11);
  ASSERT_TRUE(answer) << diagnostics();
  EXPECT_EQ(hex(answer->pdu), "86 01");
  EXPECT_EQ(heard(rtu_frame(plc, write_d11)), 0u) << diagnostics();
}

// modbus.gateway.cache: an equal read within the window is answered without the line, to
// any client, with its own transaction id; after the window it goes on the line again; a
// write to the unit empties its cache. Each answer from the cache is a monitor line, Cached.
TEST_F(GatewayTest, AnEqualReadWithinTheCacheWindowIsAnsweredWithoutTheLine) {
  start_with("{ units: [5-7], timeout: 300ms, cache: 600ms }");
  ASSERT_EQ(sim->control("set 5 0 4660"), "ok");  // D0 = 0x1234
  const Bytes read{0x03, 0x00, 0x00, 0x00, 0x01};
  auto first = Socket::tcp(config.modbus_port);
  auto second = Socket::tcp(config.modbus_port);
  const auto asked = ask(first, 0x0101, plc, read);
  const auto again = ask(second, 0x0202, plc, read);
  ASSERT_TRUE(asked && again) << diagnostics();
  EXPECT_EQ(hex(asked->pdu), "03 02 12 34");
  EXPECT_EQ(again->transaction, 0x0202);
  EXPECT_EQ(again->unit, plc);
  EXPECT_EQ(hex(again->pdu), "03 02 12 34");
  EXPECT_EQ(heard(rtu_frame(plc, read)), 1u) << diagnostics();

  // Asked again until the window is over: answered from the cache until then, then once
  // more from the line.
  std::uint16_t transaction = 0x0103;
  ASSERT_TRUE(eventually([&] { return ask(first, transaction++, plc, read) && heard(rtu_frame(plc, read)) == 2; }))
      << diagnostics();
  EXPECT_EQ(heard(rtu_frame(plc, read)), 2u) << diagnostics();

  // A write between two reads empties the unit's cache: the next read goes on the line.
  const auto written = ask(second, 0x0204, plc, {0x06, 0x00, 0x00, 0x00, 0x2A});
  ASSERT_TRUE(written);
  EXPECT_EQ(written->pdu[0], 0x06);
  const auto after_write = ask(first, 0x0105, plc, read);
  ASSERT_TRUE(after_write);
  EXPECT_EQ(hex(after_write->pdu), "03 02 00 2A");
  EXPECT_EQ(heard(rtu_frame(plc, read)), 3u) << diagnostics();

  std::string log;
  const auto cached_line = " gw:127.0.0.1:" + std::to_string(second.local_port()) + " ";
  ASSERT_TRUE(eventually([&] {
    log = read_file(monitor_log());
    return log.find("State=Cached Ad=5 PDU=03 00 00 00 01") != std::string::npos;
  })) << log;
  const auto cached = log.find("State=Cached Ad=5 PDU=03 00 00 00 01 CRC=");
  ASSERT_NE(cached, std::string::npos) << log;
  EXPECT_EQ(log.rfind(cached_line, cached), log.rfind(" gw:", cached)) << log;
  EXPECT_NE(log.find("Response=05 03 02 12 34", cached), std::string::npos) << log;
  // The second client's answer and the reads asked again within the window came from the
  // cache (all but the last of those, which went on the line); the others went on the line.
  const auto cached_lines = [&] {
    log = read_file(monitor_log());  // the monitor's writer may still have the last lines
    std::size_t n = 0;
    for (auto at = log.find("State=Cached"); at != std::string::npos; at = log.find("State=Cached", at + 1)) ++n;
    return n;
  };
  EXPECT_TRUE(eventually([&] { return cached_lines() >= static_cast<std::size_t>(transaction - 0x0103); })) << log;
  EXPECT_EQ(cached_lines(), static_cast<std::size_t>(transaction - 0x0103)) << log;
}

// An exception or a time-out is never an answer to keep: the next equal read goes on the line.
TEST_F(GatewayTest, AnExceptionOrATimeOutIsNotCached) {
  start_with("{ units: [5-7], timeout: 300ms, cache: 5s }");
  auto socket = Socket::tcp(config.modbus_port);
  const Bytes no_function{0x04, 0x00, 0x00, 0x00, 0x01};  // the PLC lacks function 4
  const Bytes read{0x03, 0x00, 0x00, 0x00, 0x01};
  for (const std::uint16_t transaction : {1, 2}) {
    const auto refused = ask(socket, transaction, plc, no_function);
    ASSERT_TRUE(refused) << diagnostics();
    EXPECT_EQ(hex(refused->pdu), "84 01");
    const auto timed_out = ask(socket, transaction, dead, read);
    ASSERT_TRUE(timed_out) << diagnostics();
    EXPECT_EQ(hex(timed_out->pdu), "83 0B");
  }
  EXPECT_EQ(heard(rtu_frame(plc, no_function)), 2u) << diagnostics();
  EXPECT_EQ(heard(rtu_frame(dead, read)), 2u) << diagnostics();
}

TEST_F(GatewayTest, WithTheCacheOffEveryReadGoesOnTheLine) {
  start_with("{ units: [5-7], timeout: 300ms, cache: 0ms }");
  auto socket = Socket::tcp(config.modbus_port);
  const Bytes read{0x03, 0x00, 0x00, 0x00, 0x01};
  for (const std::uint16_t transaction : {1, 2, 3}) ASSERT_TRUE(ask(socket, transaction, plc, read)) << diagnostics();
  EXPECT_EQ(heard(rtu_frame(plc, read)), 3u) << diagnostics();
  std::string log;
  const auto lines_on_the_line = [&] {
    std::size_t n = 0;
    for (auto at = log.find("State=Done Ad=5 PDU=03 00 00 00 01"); at != std::string::npos;
         at = log.find("State=Done Ad=5 PDU=03 00 00 00 01", at + 1))
      ++n;
    return n;
  };
  ASSERT_TRUE(eventually([&] {
    log = read_file(monitor_log());
    return lines_on_the_line() >= 3;
  })) << log;
  EXPECT_EQ(log.find("State=Cached"), std::string::npos) << log;
}

}  // namespace
}  // namespace unima::test
