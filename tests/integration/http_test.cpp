// The HTTP server of SPEC §13 with the real daemon: /metrics checked by Prometheus' own
// promtool and read before and after Modbus traffic, /healthz, /api/status,
// /api/registers with a value fed a moment before, what a read-only server refuses, the
// page's embedded files and its live feed /api/events.

#include <algorithm>
#include <csignal>
#include <optional>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "tests/integration/bridge_fixture.hpp"
#include "tests/support/peers/event_stream.hpp"
#include "tests/support/peers/http_exchange.hpp"
#include "tests/support/prometheus_sample.hpp"

namespace unima::test {
namespace {

using test_support::prometheus_sample;

using test_support::EventStream;
using test_support::http_exchange;
using test_support::http_get;


class Http : public BridgeTest {
 protected:
  void start_http() {
    http_port = free_port();
    config.extra += "http: { listen: 127.0.0.1, port: " + std::to_string(http_port) + " }\n";
    start();
    ASSERT_TRUE(wait_for_port(http_port)) << daemon->log();
  }
  std::uint16_t http_port = 0;
};

TEST_F(Http, MetricsPassPromtoolAndCountModbusTraffic) {
  start_http();
  const auto before = http_get(http_port, "/metrics");
  ASSERT_EQ(before.status, 200) << before.head;
  EXPECT_NE(before.head.find("Content-Type: text/plain; version=0.0.4"), std::string::npos) << before.head;
  const auto file = dir.path() / "metrics.txt";
  test_support::write_file(file, before.body);
  const auto checked = run("promtool check metrics < " + file.string());
  EXPECT_EQ(checked.status, 0) << checked.output << before.body;

  const std::string done = R"(unima_bridge_modbus_transactions_total{port="tcp",state="Done"})";
  const auto done_before = prometheus_sample(before.body, done);
  ASSERT_TRUE(done_before) << before.body;
  {
    ModbusClient client(config.modbus_port);
    for (int i = 0; i < 5; ++i) ASSERT_TRUE(client.read_input(0x0011, 1));
    EXPECT_FALSE(client.read_input(0x0012 + 0x40, 1));  // past D1: an Err02
  }
  const auto after = http_get(http_port, "/metrics").body;
  EXPECT_EQ(prometheus_sample(after, done), *done_before + 5) << after;
  EXPECT_EQ(prometheus_sample(after, R"(unima_bridge_modbus_transactions_total{port="tcp",state="Err02"})"), 1) << after;
  EXPECT_EQ(prometheus_sample(after, "unima_bridge_feed_clients"), 0) << after;
  EXPECT_GT(prometheus_sample(after, "unima_bridge_resident_memory_bytes").value_or(0), 1e6) << after;
}

TEST_F(Http, HealthStatusAndRegistersWithTheValueFedAMomentBefore) {
  start_http();
  const auto health = http_get(http_port, "/healthz");
  EXPECT_EQ(health.status, 200);
  EXPECT_EQ(health.body, "ok\n");

  auto feed = feed_client();
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":1,"values":[1234]})", 0x0012, 1234);
  const auto status = nlohmann::json::parse(http_get(http_port, "/api/status").body);
  EXPECT_EQ(status["devices"][0]["online"], true) << status.dump();
  EXPECT_EQ(status["unimabus"]["clients"], 1) << status.dump();

  const auto registers = nlohmann::json::parse(http_get(http_port, "/api/registers").body);
  bool found = false;
  for (const auto& r : registers)
    if (r["address"] == "0x0012") {
      found = true;
      EXPECT_EQ(r["id"], "engine_speed") << r.dump();
      EXPECT_EQ(r["value"], 1234) << r.dump();
      // SPEC §17: beside the raw register, the value model's values read from it.
      ASSERT_EQ(r["values"].size(), 1u) << r.dump();
      EXPECT_EQ(r["values"][0]["name"], "engine_speed") << r.dump();
      EXPECT_EQ(r["values"][0]["value"], 1234) << r.dump();
      EXPECT_EQ(r["values"][0]["unit"], "min-1") << r.dump();
      EXPECT_EQ(r["values"][0]["state"], "ok") << r.dump();
    } else if (r["address"] == "0x0014") {  // operating_hours_high: no telegram carried it
      EXPECT_EQ(r["values"][0], (nlohmann::json{{"name", "operating_hours"}, {"value", nullptr}, {"unit", "s"},
                                                {"state", "not measured"}, {"label", "Motohodiny"}, {"bank", "D1"},
                                                {"type", "number"}}))
          << r.dump();
    } else if (r["bank"] == "W" && r["offset"] == 0) {
      EXPECT_EQ(r["values"][0]["set"], false) << "never written: " << r.dump();
    }
  EXPECT_TRUE(found) << registers.dump();
}

// A read block (MBS_RegR) lists its source's value, in its unit, as the page shows it.
TEST_F(Http, ARegistersReadBlockHasItsSourcesValue) {
  config.blocks = "  - { type: read, register: 0x0200, source: D1.engine_speed }\n";
  start_http();
  auto feed = feed_client();
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":1,"values":[1234]})", 0x0012, 1234);
  const auto registers = nlohmann::json::parse(http_get(http_port, "/api/registers").body);
  const auto block = std::find_if(registers.begin(), registers.end(), [](const auto& r) { return r["address"] == "0x0200"; });
  ASSERT_NE(block, registers.end()) << registers.dump();
  EXPECT_EQ((*block)["value"], 1234) << block->dump();
  EXPECT_EQ((*block)["values"], (nlohmann::json::array({{{"name", "engine_speed"}, {"bank", "D1"}, {"value", 1234},
                                                          {"unit", "min-1"}, {"state", "ok"}, {"label", "Otáčky"},
                                                          {"type", "number"}}})))
      << block->dump();
}

// The loop stopped for 2.5 s (SIGSTOP): /healthz says so once it turns again, for a few
// seconds, then is back to ok.
TEST_F(Http, HealthzReportsAStalledLoop) {
  start_http();
  ASSERT_EQ(http_get(http_port, "/healthz").status, 200);
  daemon->signal(SIGSTOP);
  std::this_thread::sleep_for(2500ms);  // the stall under test, longer than /healthz allows
  daemon->signal(SIGCONT);
  const auto stalled = http_get(http_port, "/healthz");
  EXPECT_EQ(stalled.status, 503) << stalled.body;
  EXPECT_NE(stalled.body.find("stalled: the event loop did not turn for"), std::string::npos) << stalled.body;
  EXPECT_TRUE(eventually([&] { return http_get(http_port, "/healthz").status == 200; }, 8000ms));
}

TEST_F(Http, ReadOnlyAndBounded) {
  start_http();
  const auto post = http_exchange(http_port, "POST /metrics HTTP/1.1\r\nHost: x\r\nContent-Length: 0\r\nConnection: close\r\n\r\n");
  EXPECT_EQ(post.status, 405) << post.head;
  EXPECT_NE(post.head.find("Allow: GET, HEAD"), std::string::npos) << post.head;
  EXPECT_EQ(http_get(http_port, "/nothing").status, 404);
  const auto huge = http_exchange(http_port, "GET /metrics HTTP/1.1\r\nHost: x\r\nX-Big: " + std::string(10000, 'a') + "\r\n\r\n");
  EXPECT_EQ(huge.status, 431) << huge.head;
  const auto head = http_exchange(http_port, "HEAD /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  EXPECT_EQ(head.status, 200);
  EXPECT_EQ(head.body, "");
  EXPECT_NE(head.head.find("Content-Length: 3"), std::string::npos) << head.head;
  // Nothing of this disturbed the daemon: it still answers.
  EXPECT_EQ(http_get(http_port, "/healthz").status, 200);
}

TEST_F(Http, ThePageAndItsFilesComeFromTheBinaryAndNothingElse) {
  start_http();
  const auto page = http_get(http_port, "/");
  ASSERT_EQ(page.status, 200) << page.head;
  EXPECT_NE(page.head.find("Content-Type: text/html; charset=utf-8"), std::string::npos) << page.head;
  EXPECT_NE(page.head.find("Content-Security-Policy: default-src 'self'"), std::string::npos) << page.head;
  EXPECT_NE(page.body.find("<script src=\"/panel.js\""), std::string::npos) << page.body;
  // Every file the page names is served, and the page names nothing from elsewhere.
  EXPECT_EQ(page.body.find("http"), std::string::npos) << page.body;
  const auto script = http_get(http_port, "/panel.js");
  EXPECT_EQ(script.status, 200);
  EXPECT_NE(script.head.find("Content-Type: text/javascript"), std::string::npos) << script.head;
  EXPECT_NE(script.body.find("new EventSource(api('/api/events?'"), std::string::npos);
  // Its paths on its own origin, whatever name and password the page's address holds.
  EXPECT_NE(script.body.find("new URL(path, location.origin)"), std::string::npos);
  EXPECT_EQ(http_get(http_port, "/panel.css").status, 200);
  EXPECT_EQ(http_get(http_port, "/index.html").status, 200);
  for (const auto* path : {"/../index.html", "/web/panel.js", "/panel.js/", "//panel.js", "/CMakeLists.txt"})
    EXPECT_EQ(http_get(http_port, path).status, 404) << path;
}

// What the page lives on: the whole picture on connecting, then what changed and only
// that — one register fed, one register in the next event — and the panel when a
// device comes on line.
TEST_F(Http, EventsSendTheWholePictureThenOnlyWhatChanged) {
  start_http();
  EventStream events(http_port, "/api/events");
  const auto head = events.head();
  EXPECT_NE(head.find("200 OK"), std::string::npos) << head;
  EXPECT_NE(head.find("Content-Type: text/event-stream"), std::string::npos) << head;
  const auto panel = events.next("panel");
  ASSERT_TRUE(panel);
  EXPECT_EQ((*panel)["devices"][0]["bank"], "D1");
  EXPECT_EQ((*panel)["devices"][0]["online"], false) << panel->dump();
  const auto all = events.next("registers");
  ASSERT_TRUE(all);
  EXPECT_GT(all->size(), 50u);
  EXPECT_EQ((*all)["0x0012"], 0x7FFF) << "not measured before anything was fed";
  const auto all_values = events.next("values");
  ASSERT_TRUE(all_values);
  EXPECT_EQ((*all_values)["D1/engine_speed"], (nlohmann::json{{"value", nullptr}, {"state", "off-line"}}));
  EXPECT_EQ((*all_values)["W/w_00"], (nlohmann::json{{"value", nullptr}, {"state", "not set"}, {"set", false}}));

  auto feed = feed_client();
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":1,"values":[1234]})", 0x0012, 1234);
  const auto changed = events.next("registers");
  ASSERT_TRUE(changed);
  // The value fed, and D1's bit in C+0x13 (bank C at its default 0x1020): nothing else.
  EXPECT_EQ(*changed, (nlohmann::json{{"0x0012", 1234}, {"0x1033", 1}}));
  const auto changed_values = events.next("values");
  ASSERT_TRUE(changed_values);
  EXPECT_EQ((*changed_values)["D1/engine_speed"], (nlohmann::json{{"value", 1234}, {"state", "ok"}}));
  EXPECT_EQ((*changed_values)["D1/oil_temperature"], (nlohmann::json{{"value", nullptr}, {"state", "not measured"}}))
      << "on line, never fed";
  EXPECT_FALSE(changed_values->contains("W/w_00")) << "only what changed";
  const auto online = events.next("panel");
  ASSERT_TRUE(online);
  EXPECT_EQ((*online)["devices"][0]["online"], true) << online->dump();

  // Nothing changes: nothing is sent (the page's feed costs nothing while the plant is still).
  EXPECT_FALSE(events.next("registers", 1000ms));
}

// The monitor pane: the last lines of every port through the page's own filter, in the
// words of `monitor --filter`; a filter that is not one is refused with the reason.
TEST_F(Http, EventsCarryMonitorLinesThroughThePagesFilter) {
  start_http();
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.read_input(0x0011, 2));
  EventStream events(http_port, "/api/events?ad=xx&fn=3&from=0x0011&to=0x0011");
  const auto first = events.next("monitor");
  ASSERT_TRUE(first);
  EXPECT_EQ((*first)["lines"].size(), 0u) << "the FC4 read before does not pass fn=3: " << first->dump();
  ASSERT_TRUE(client.read_input(0x0011, 1));
  ASSERT_TRUE(client.read_holding(0x0100, 1) || true);  // fn 3 elsewhere: filtered by register
  ASSERT_TRUE(client.read_holding(0x0011, 1));
  const auto lines = events.next("monitor");
  ASSERT_TRUE(lines);
  ASSERT_EQ((*lines)["lines"].size(), 1u) << lines->dump();
  const std::string line = (*lines)["lines"][0];
  EXPECT_NE(line.find(" tcp:127.0.0.1:"), std::string::npos) << line;
  EXPECT_NE(line.find("PDU=03 00 11 00 01"), std::string::npos) << line;

  const auto refused = http_get(http_port, "/api/events?fn=300");
  EXPECT_EQ(refused.status, 400);
  EXPECT_NE(refused.body.find("'300' is not xx or a number 0..255"), std::string::npos) << refused.body;
}

// The alert rules docs/operations.md offers are valid rules for Prometheus.
TEST(HttpDocs, TheAlertRulesOfTheOperationsGuidePassPromtool) {
  const auto guide = read_file(std::string(UNIMA_SOURCE_DIR) + "/docs/operations.md");
  const auto start = guide.find("```yaml\ngroups:");
  ASSERT_NE(start, std::string::npos);
  const auto end = guide.find("```\n", start + 7);
  TempDir dir;
  const auto rules = dir.path() / "rules.yml";
  test_support::write_file(rules, guide.substr(start + 8, end - start - 8));
  const auto checked = run("promtool check rules " + rules.string());
  EXPECT_EQ(checked.status, 0) << checked.output;
  EXPECT_NE(checked.output.find("SUCCESS: 4 rules found"), std::string::npos) << checked.output;
}

}  // namespace
}  // namespace unima::test
