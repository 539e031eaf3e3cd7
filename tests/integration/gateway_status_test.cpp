// The gateway seen and counted (SPEC §14, issue 31, 4): per unit, what its clients got and
// whether the slave answers, in the status document, `unima-bridge status`, /metrics
// (promtool) and the page (headless Chromium); a forwarded fault lights the Error LED as a
// poll's does; a client that goes takes its queued requests with it.

#include <atomic>
#include <future>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "tests/integration/certificate_fixture.hpp"
#include "tests/integration/cli_under_test.hpp"
#include "tests/integration/gateway_fixture.hpp"
#include "tests/support/peers/http_exchange.hpp"
#include "tests/support/prometheus_sample.hpp"

namespace unima::test {
namespace {

using test_support::prometheus_sample;

const Bytes read_d0{0x03, 0x00, 0x00, 0x00, 0x01};

Bytes read_d(std::uint8_t reg) { return {0x03, 0x00, reg, 0x00, 0x01}; }

// A raw request as a client pipelines it, without waiting for its answer.
Bytes adu(std::uint16_t transaction, std::uint8_t unit, const Bytes& pdu) {
  const auto length = pdu.size() + 1;
  Bytes out{static_cast<std::uint8_t>(transaction >> 8), static_cast<std::uint8_t>(transaction), 0, 0,
            static_cast<std::uint8_t>(length >> 8), static_cast<std::uint8_t>(length), unit};
  out.insert(out.end(), pdu.begin(), pdu.end());
  return out;
}


class GatewayStatusTest : public GatewayTest {
 protected:
  std::string status_text() const { return run(bridge_cli() + " status --socket " + config.status_socket).output; }
  bool error_led() {
    ModbusClient client(config.modbus_port);
    const auto bits = client.read_input(online_bits, 1);
    return bits && ((*bits)[0] & 0x8000) != 0;
  }
  void with_http() {
    http_port = free_port();
    config.extra += "http: { listen: 127.0.0.1, port: " + std::to_string(http_port) + " }\n";
  }
  std::uint16_t http_port = 0;
};

// A dead unit's client gets 0B while a live unit's client keeps getting its answers; after
// three failures in a row the dead unit is "not answering since" the first, in the status
// document, the CLI's table and /metrics, with one warning; back, it is "answering" again
// with one info line.
TEST_F(GatewayStatusTest, ADeadUnitIsShownNotAnsweringWhileTheLiveOneIsServedAndAnswersAgain) {
  with_http();
  start_with("{ units: [5-7], timeout: 200ms, wait: 5s }");
  ASSERT_TRUE(wait_for_port(http_port)) << diagnostics();

  std::atomic<bool> stop{false};
  auto live = std::async(std::launch::async, [&] {
    auto socket = Socket::tcp(config.modbus_port);
    std::size_t answered = 0, other = 0;
    for (std::uint16_t t = 1; !stop; ++t) {
      const auto answer = ask(socket, t, plc, read_d0);
      if (answer && answer->pdu.size() == 4 && answer->pdu[0] == 0x03) ++answered;
      else ++other;
    }
    return std::pair(answered, other);
  });
  auto socket = Socket::tcp(config.modbus_port);
  for (std::uint16_t t = 1; t <= 4; ++t) {
    const auto answer = ask(socket, t, dead, read_d0);
    ASSERT_TRUE(answer) << diagnostics();
    EXPECT_EQ(hex(answer->pdu), "83 0B");
  }
  stop = true;
  const auto [answered, other] = live.get();
  EXPECT_GE(answered, 4u) << diagnostics();  // four time-outs of 200 ms: the live unit was served meanwhile
  EXPECT_EQ(other, 0u) << diagnostics();

  const auto silent = unit_status(dead);
  ASSERT_TRUE(silent.is_object()) << status().dump(1);
  EXPECT_EQ(silent["state"], "not answering") << silent;
  EXPECT_TRUE(silent["since"].is_string()) << silent;
  EXPECT_EQ(silent["requests"], 4) << silent;
  EXPECT_EQ(silent["timeouts"], 4) << silent;
  EXPECT_EQ(silent["answered"], 0) << silent;
  EXPECT_EQ(silent["queue_depth"], 0) << silent;
  const auto alive = unit_status(plc);
  ASSERT_TRUE(alive.is_object()) << status().dump(1);
  EXPECT_EQ(alive["state"], "answering") << alive;
  EXPECT_TRUE(alive["since"].is_null()) << alive;
  EXPECT_EQ(alive["answered"], alive["requests"]) << alive;
  EXPECT_GE(alive["answered"].get<int>(), 4) << alive;
  EXPECT_EQ(alive["wait_ms"]["count"], alive["requests"]) << alive;
  const auto gateway = status()["gateway"];
  EXPECT_EQ(gateway["routes"], "5-7") << gateway;
  EXPECT_EQ(gateway["wait_ms"], 5000) << gateway;
  EXPECT_EQ(gateway["timeout_ms"], 200) << gateway;
  // Unit 6 is polled, but no client asked for it: no row.
  EXPECT_TRUE(unit_status(stepper).is_null()) << gateway;

  const auto text = status_text();
  EXPECT_NE(text.find("Gateway     units 5-7, wait 5000 ms, timeout 200 ms, cache off"), std::string::npos) << text;
  EXPECT_NE(text.find("not answering since " + silent["since"].get<std::string>()), std::string::npos) << text;
  EXPECT_NE(text.find("answering\n"), std::string::npos) << text;

  const auto metrics = test_support::http_get(http_port, "/metrics");
  ASSERT_EQ(metrics.status, 200);
  const auto file = dir.path() / "metrics.txt";
  test_support::write_file(file, metrics.body);
  const auto checked = run("promtool check metrics < " + file.string());
  EXPECT_EQ(checked.status, 0) << checked.output << metrics.body;
  EXPECT_EQ(prometheus_sample(metrics.body, R"(unima_bridge_gateway_answering{unit="7"})"), 0) << metrics.body;
  EXPECT_EQ(prometheus_sample(metrics.body, R"(unima_bridge_gateway_answering{unit="5"})"), 1) << metrics.body;
  EXPECT_EQ(prometheus_sample(metrics.body, R"(unima_bridge_gateway_timeouts_total{unit="7"})"), 4) << metrics.body;
  EXPECT_GE(prometheus_sample(metrics.body, R"(unima_bridge_gateway_requests_total{unit="5"})").value_or(0), 4) << metrics.body;

  const auto warning = "modbus gateway: unit 7 is not answering";
  EXPECT_EQ(daemon->log_count(warning), 1u) << "one warning, not one per failure\n" << daemon->log();

  ASSERT_EQ(sim->control("dead 7 off"), "ok");
  const auto back = ask(socket, 5, dead, read_d0);
  ASSERT_TRUE(back) << diagnostics();
  EXPECT_EQ(back->pdu[0], 0x03) << hex(back->pdu);
  const auto again = unit_status(dead);
  EXPECT_EQ(again["state"], "answering") << again;
  EXPECT_TRUE(again["since"].is_null()) << again;
  EXPECT_EQ(again["answered"], 1) << again;
  EXPECT_TRUE(daemon->wait_for_log("modbus gateway: unit 7 answers again")) << daemon->log();
}

// Each counter of a unit: the wait of a request behind a slow slave's, a cache hit that
// does not go on the line, the queue depth while a request waits, its busy refusal, and
// the slave's own exception.
TEST_F(GatewayStatusTest, EachCounterOfAUnitCountsWhatItsClientsGot) {
  start_with("{ units: [5-7], timeout: 1500ms, wait: 1s, cache: 10s }");
  auto first = Socket::tcp(config.modbus_port);
  auto second = Socket::tcp(config.modbus_port);

  // The PLC takes 400 ms: the second request waits about that long for the line.
  ASSERT_EQ(sim->control("slow 5 400"), "ok");
  first.send(adu(1, plc, read_d(0)));
  ASSERT_TRUE(sim->wait_for_frame(hex(rtu_frame(plc, read_d(0))))) << diagnostics();
  second.send(adu(2, plc, read_d(1)));
  ASSERT_EQ(first.receive(11).size(), 11u) << diagnostics();
  ASSERT_EQ(second.receive(11, 3000ms).size(), 11u) << diagnostics();
  auto plc_row = unit_status(plc);
  EXPECT_EQ(plc_row["requests"], 2) << plc_row;
  EXPECT_EQ(plc_row["answered"], 2) << plc_row;
  EXPECT_EQ(plc_row["wait_ms"]["count"], 2) << plc_row;
  EXPECT_GE(plc_row["wait_ms"]["max"].get<double>(), 200.0) << plc_row;
  EXPECT_LE(plc_row["wait_ms"]["max"].get<double>(), 1000.0) << plc_row;  // within `wait`, or it were busy
  EXPECT_GE(plc_row["wait_ms"]["mean"].get<double>(), 100.0) << plc_row;

  // An equal read within the cache's window: answered, counted, not on the line.
  ASSERT_TRUE(ask(first, 3, plc, read_d(0))) << diagnostics();
  EXPECT_EQ(heard(rtu_frame(plc, read_d(0))), 1u) << diagnostics();
  plc_row = unit_status(plc);
  EXPECT_EQ(plc_row["cache_hits"], 1) << plc_row;
  EXPECT_EQ(plc_row["requests"], 2) << plc_row;

  // The dead unit holds the line for its 1.5 s time-out; a request for the PLC waits in the
  // queue, then leaves it busy at its 1 s wait.
  ASSERT_EQ(sim->control("slow 5 0"), "ok");
  first.send(adu(4, dead, read_d0));
  ASSERT_TRUE(sim->wait_for_frame(hex(rtu_frame(dead, read_d0)))) << diagnostics();
  second.send(adu(5, plc, read_d(2)));
  EXPECT_TRUE(eventually([&] { return unit_status(plc)["queue_depth"] == 1; }, 900ms)) << status().dump(1);
  const auto busy = second.receive(9);
  ASSERT_EQ(busy.size(), 9u) << diagnostics();
  EXPECT_EQ(busy[7], 0x83);
  EXPECT_EQ(busy[8], 0x06);
  ASSERT_EQ(first.receive(9).size(), 9u) << diagnostics();
  plc_row = unit_status(plc);
  EXPECT_EQ(plc_row["busy"], 1) << plc_row;
  EXPECT_EQ(plc_row["queue_depth"], 0) << plc_row;
  const auto dead_row = unit_status(dead);
  EXPECT_EQ(dead_row["timeouts"], 1) << dead_row;
  EXPECT_EQ(dead_row["state"], "answering") << "one failure is not silence: " << dead_row;

  // The slave's own exception: function 4 is one the PLC lacks.
  const auto refused = ask(first, 6, plc, {0x04, 0x00, 0x00, 0x00, 0x01});
  ASSERT_TRUE(refused) << diagnostics();
  EXPECT_EQ(hex(refused->pdu), "84 01");
  plc_row = unit_status(plc);
  EXPECT_EQ(plc_row["exceptions"], 1) << plc_row;
  EXPECT_EQ(plc_row["state"], "answering") << plc_row;
  EXPECT_EQ(plc_row["requests"], 3) << plc_row;
}

// SPEC §8: a forwarded transaction's time-out lights the Error LED (C+0x13 bit 15) as a
// poll's does, and so does the slave's exception, as a poll's exception does.
TEST_F(GatewayStatusTest, AForwardedFaultLightsTheErrorLedAsAPollsDoes) {
  start_with("{ units: [5-7], timeout: 200ms }");
  ASSERT_TRUE(output_becomes(1, 8)) << diagnostics();
  // The polls answer: nothing lights it but the gateway's transactions.
  ASSERT_TRUE(eventually([&] { return !error_led(); }, 5000ms)) << diagnostics();
  auto socket = Socket::tcp(config.modbus_port);
  ASSERT_TRUE(ask(socket, 1, plc, read_d0));
  EXPECT_FALSE(error_led()) << "a good answer is no fault";
  const auto timed_out = ask(socket, 2, dead, read_d0);
  ASSERT_TRUE(timed_out) << diagnostics();
  EXPECT_EQ(hex(timed_out->pdu), "83 0B");
  EXPECT_TRUE(error_led()) << diagnostics();
  EXPECT_EQ(status()["error"], true);
  ASSERT_TRUE(eventually([&] { return !error_led(); }, 5000ms)) << "the 2 s hold ends";
  const auto exception = ask(socket, 3, plc, {0x04, 0x00, 0x00, 0x00, 0x01});
  ASSERT_TRUE(exception) << diagnostics();
  EXPECT_EQ(hex(exception->pdu), "84 01");
  EXPECT_TRUE(error_led()) << diagnostics();
}

// A client that closes its connection while its request waits for the line: the request
// leaves the queue and never goes on the line, and the gateway serves the next client.
TEST_F(GatewayStatusTest, AClientThatGoesTakesItsQueuedRequestWithIt) {
  start_with("{ units: [5-7], timeout: 1500ms, wait: 3s }");
  ASSERT_EQ(sim->control("slow 5 1000"), "ok");
  auto holder = Socket::tcp(config.modbus_port);
  holder.send(adu(1, plc, read_d(0)));
  ASSERT_TRUE(sim->wait_for_frame(hex(rtu_frame(plc, read_d(0))))) << diagnostics();
  {
    auto leaving = Socket::tcp(config.modbus_port);
    leaving.send(adu(2, plc, read_d(9)));
    ASSERT_TRUE(eventually([&] { return unit_status(plc)["queue_depth"] == 1; }, 800ms)) << status().dump(1);
    leaving.close();
  }
  EXPECT_TRUE(eventually([&] { return unit_status(plc)["queue_depth"] == 0; }, 500ms)) << status().dump(1);
  ASSERT_EQ(holder.receive(11).size(), 11u) << diagnostics();
  // Past the time its request would have gone on the line.
  ASSERT_EQ(sim->control("slow 5 0"), "ok");
  const auto next = ask(holder, 3, plc, read_d(1));
  ASSERT_TRUE(next) << diagnostics();
  EXPECT_EQ(next->pdu[0], 0x03);
  EXPECT_EQ(heard(rtu_frame(plc, read_d(9))), 0u) << diagnostics();
  EXPECT_EQ(unit_status(plc)["requests"], 2);
  EXPECT_TRUE(daemon->wait_for_log("1 of its requests left the queue")) << daemon->log();
  EXPECT_TRUE(daemon->running()) << daemon->log();
}

// The same over the TLS port: the client's close_notify is seen while its request waits.
TEST_F(GatewayStatusTest, ATlsClientThatGoesTakesItsQueuedRequestWithIt) {
  const auto certs = dir.path() / "certs";
  const auto made = run(tls_dir + "/make_certificates.sh " + certs.string());
  ASSERT_EQ(made.status, 0) << made.output;
  const auto pem = [&](const std::string& name) { return (certs / name).string(); };
  const auto tls_port = free_port();
  start_with("{ units: [5-7], timeout: 3s, wait: 5s }",
             "  tls: { listen: 127.0.0.1, port: " + std::to_string(tls_port) + ", certificate: " + pem("server.pem") +
                 ", key: " + pem("server.key") + ", ca: " + pem("ca.pem") + ", roles: { viewer: { write: [W] } } }\n");
  ASSERT_TRUE(wait_for_port(tls_port)) << diagnostics();
  // The holder's read takes the line for 2 s: time for the TLS client to connect, ask and go.
  ASSERT_EQ(sim->control("slow 5 2000"), "ok");
  auto holder = Socket::tcp(config.modbus_port);
  holder.send(adu(1, plc, read_d(0)));
  ASSERT_TRUE(sim->wait_for_frame(hex(rtu_frame(plc, read_d(0))))) << diagnostics();
  const auto left = run(tls_dir + "/modbus_tls_client.py --unit 5 --leave 300 " + std::to_string(tls_port) + " " +
                        pem("ca.pem") + " " + pem("viewer.pem") + " " + pem("viewer.key") + " -- 0300090001");
  ASSERT_NE(left.output.find("left"), std::string::npos) << left.output;
  EXPECT_TRUE(daemon->wait_for_log("1 of its requests left the queue", 1500ms)) << daemon->log();
  ASSERT_EQ(holder.receive(11, 4000ms).size(), 11u) << diagnostics();
  ASSERT_EQ(sim->control("slow 5 0"), "ok");
  ASSERT_TRUE(ask(holder, 2, plc, read_d(1))) << diagnostics();
  EXPECT_EQ(heard(rtu_frame(plc, read_d(9))), 0u) << diagnostics();
  EXPECT_EQ(unit_status(plc)["queue_depth"], 0);
  EXPECT_TRUE(daemon->running()) << daemon->log();
}

// The page's front panel has a gateway table: the silent unit marked in red, the live one not.
TEST_F(GatewayStatusTest, ThePageShowsTheGatewayUnitsAndMarksTheSilentOne) {
  with_http();
  start_with("{ units: [5-7], timeout: 200ms }");
  ASSERT_TRUE(wait_for_port(http_port)) << diagnostics();
  auto socket = Socket::tcp(config.modbus_port);
  ASSERT_TRUE(ask(socket, 1, plc, read_d0));
  for (std::uint16_t t = 2; t <= 4; ++t) ASSERT_TRUE(ask(socket, t, dead, read_d0)) << diagnostics();
  ASSERT_EQ(unit_status(dead)["state"], "not answering") << status().dump(1);

  const auto command = std::string(UNIMA_SOURCE_DIR) + "/tests/integration/browser/page_in_chromium.py --url http://127.0.0.1:" +
                       std::to_string(http_port) + "/ --gateway '7=not answering' --gateway 5=answering --timeout 30 2>&1";
  const auto result = run(command);
  ASSERT_EQ(result.status, 0) << result.output;
  const auto shown = nlohmann::json::parse(result.output.substr(result.output.rfind("{\"ok\"")), nullptr, false);
  ASSERT_TRUE(shown.contains("gateway")) << result.output;
  const auto& rows = shown["gateway"];
  EXPECT_NE(rows["7"]["text"].get<std::string>().find("not answering since"), std::string::npos) << rows;
  EXPECT_EQ(rows["7"]["colour"], "rgb(210, 47, 47)") << rows;  // --err
  EXPECT_NE(rows["5"]["colour"], "rgb(210, 47, 47)") << rows;
}

}  // namespace
}  // namespace unima::test
