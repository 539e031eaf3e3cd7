// The front page's northbound box (issue 32, 5; issue 33, 4) in headless Chromium against a
// real mosquitto: MQTT connected with its client id; once the broker is gone, not connected
// since when, in the error colour, with the documents the history buffer holds for it —
// as `unima-bridge status` and /metrics say too; the Sparkplug session with its bdSeq. Only
// the configured sections appear.

#include <regex>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "tests/integration/bridge_fixture.hpp"
#include "tests/integration/cli_under_test.hpp"
#include "tests/support/peers/http_exchange.hpp"
#include "tests/support/peers/mqtt_broker.hpp"
#include "tests/support/prometheus_sample.hpp"

namespace unima::test {
namespace {

using test_support::prometheus_sample;

using test_support::Broker;

constexpr auto error_colour = "rgb(210, 47, 47)";  // panel.css --err


class PageNorth : public BridgeTest {
 protected:
  void SetUp() override {
    BridgeTest::SetUp();
    broker = std::make_unique<Broker>(dir.path());
    ASSERT_TRUE(broker->start());
    http_port = free_port();
    config.extra += "http: { listen: 127.0.0.1, port: " + std::to_string(http_port) + " }\n";
  }
  void start_bridge() {
    start();
    ASSERT_TRUE(wait_for_port(http_port)) << daemon->log();
  }
  nlohmann::json status() const {
    return nlohmann::json::parse(run(bridge_cli() + " status --json --socket " + config.status_socket).output, nullptr, false);
  }
  std::string broker_url() const { return "mqtt://127.0.0.1:" + std::to_string(broker->port()); }

  /// Opens the page until each `section=text` shows (and its Config box has loaded); its
  /// northbound sections as the page showed them, the Config box in `config_box`.
  nlohmann::json page_north(const std::vector<std::string>& expected) {
    auto command = std::string(UNIMA_SOURCE_DIR) + "/tests/integration/browser/page_in_chromium.py --url http://127.0.0.1:" +
                   std::to_string(http_port) + "/ --timeout 30 --config-box";
    for (const auto& e : expected) command += " --north '" + e + "'";
    const auto result = run(command + " 2>&1");
    EXPECT_EQ(result.status, 0) << result.output << daemon->log();
    const auto at = result.output.rfind("{\"ok\"");
    if (at == std::string::npos) return {};
    const auto shown = nlohmann::json::parse(result.output.substr(at), nullptr, false);
    if (shown.contains("config")) config_box = shown["config"];
    return shown.contains("north") ? shown["north"] : nlohmann::json();
  }

  std::unique_ptr<Broker> broker;
  std::uint16_t http_port = 0;
  nlohmann::json config_box;
};

/// The line of `section` that starts with `start`; empty when none does.
nlohmann::json line_of(const nlohmann::json& section, const std::string& start) {
  for (const auto& line : section["lines"])
    if (line["text"].get<std::string>().starts_with(start)) return line;
  return {};
}

TEST_F(PageNorth, TheBoxShowsMqttConnectedWithItsClientId) {
  config.extra += test_support::site_17_mqtt(*broker);
  start_bridge();
  const auto north = page_north({"mqtt=connected to " + broker_url() + " as site-17 since "});
  ASSERT_TRUE(north.contains("mqtt")) << north;
  EXPECT_FALSE(north.contains("sparkplug")) << north;  // not configured, not shown
  const auto& mqtt = north["mqtt"];
  EXPECT_EQ(mqtt["connected"], "true") << mqtt;
  const auto connected = line_of(mqtt, "connected to");
  ASSERT_TRUE(connected.is_object()) << mqtt;
  EXPECT_NE(connected["colour"], error_colour) << mqtt;
  EXPECT_TRUE(line_of(mqtt, "last session takeover: none").is_object()) << mqtt;
  const auto dropped = line_of(mqtt, "0 dropped");
  ASSERT_TRUE(dropped.is_object()) << mqtt;
  EXPECT_NE(dropped["colour"], error_colour) << mqtt;
  // No remote_config, and no config from afar ever: the Config box stays hidden.
  EXPECT_GE(config_box.value("loaded", 0), 1) << config_box;
  EXPECT_EQ(config_box.value("hidden", false), true) << config_box;
}

// The broker stopped: not connected since the drop, in red, and what the history buffer
// holds for it; the CLI and /metrics say the same.
TEST_F(PageNorth, AfterTheBrokerStopsTheBoxShowsNotConnectedAndTheMessagesWaiting) {
  config.extra += test_support::site_17_mqtt(*broker);
  start_bridge();
  ASSERT_TRUE(eventually([&] { return status()["mqtt"]["connected"] == true; })) << daemon->log();
  auto feed = feed_client();
  broker->stop();
  ASSERT_TRUE(daemon->wait_for_log("mqtt: the connection to")) << daemon->log();
  int speed = 0;
  ASSERT_TRUE(eventually([&] {
    feed.send(R"({"addr":5,"slot":0,"offset":1,"values":[)" + std::to_string(++speed) + "]}\n");
    std::this_thread::sleep_for(std::chrono::milliseconds(150));  // one document per 100 ms at most
    const auto s = status();
    return s["mqtt"]["buffer"].is_object() && s["mqtt"]["buffer"]["messages"].get<int>() >= 2;
  }, std::chrono::milliseconds(10000))) << status().dump() << daemon->log();

  const auto north = page_north({"mqtt=not connected to " + broker_url() + " (as site-17) since "});
  ASSERT_TRUE(north.contains("mqtt")) << north;
  const auto& mqtt = north["mqtt"];
  EXPECT_EQ(mqtt["connected"], "false") << mqtt;
  EXPECT_EQ(line_of(mqtt, "not connected to")["colour"], error_colour) << mqtt;
  const auto buffer = line_of(mqtt, "history buffer: ");
  ASSERT_TRUE(buffer.is_object()) << mqtt;
  std::smatch waiting;
  const auto text = buffer["text"].get<std::string>();
  ASSERT_TRUE(std::regex_search(text, waiting, std::regex(R"(history buffer: (\d+) messages \((\d+) bytes\) waiting)"))) << text;
  EXPECT_GE(std::stoi(waiting[1]), 2) << text;
  EXPECT_GT(std::stoi(waiting[2]), 0) << text;
  EXPECT_EQ(buffer["colour"], error_colour) << mqtt;

  const auto cli = run(bridge_cli() + " status --socket " + config.status_socket).output;
  EXPECT_NE(cli.find("MQTT        not connected to " + broker_url() + " since "), std::string::npos) << cli;
  const auto metrics = test_support::http_get(http_port, "/metrics").body;
  EXPECT_EQ(prometheus_sample(metrics, "unima_bridge_mqtt_connected"), 0) << metrics;
  EXPECT_GE(prometheus_sample(metrics, "unima_bridge_mqtt_buffer_messages").value_or(0), 2) << metrics;
  // Not connected since the drop: after the daemon started, not before.
  const auto since = prometheus_sample(metrics, "unima_bridge_mqtt_state_since_timestamp_seconds");
  ASSERT_TRUE(since) << metrics;
  const auto now = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  EXPECT_LE(*since, now) << metrics;
  EXPECT_GE(*since, now - 60) << metrics;
}

// Sparkplug only: its session with the bdSeq of this connection; no MQTT section.
TEST_F(PageNorth, TheBoxShowsTheSparkplugSessionWithItsBdSeq) {
  config.extra += "sparkplug: { broker: '" + broker_url() + "', group_id: plant-7, edge_node_id: bridge-17 }\n";
  start_bridge();
  nlohmann::json session;
  ASSERT_TRUE(eventually([&] {
    session = status()["sparkplug"];
    return session.is_object() && session["born"] == true && session["bdSeq"].is_number();
  })) << status().dump() << daemon->log();
  const auto bd_seq = std::to_string(session["bdSeq"].get<int>());

  const auto north = page_north({"sparkplug=bdSeq " + bd_seq + ",", "sparkplug=connected to " + broker_url() + " and born since "});
  ASSERT_TRUE(north.contains("sparkplug")) << north;
  EXPECT_FALSE(north.contains("mqtt")) << north;
  const auto& sparkplug = north["sparkplug"];
  EXPECT_NE(sparkplug["text"].get<std::string>().find("Sparkplug: plant-7/bridge-17"), std::string::npos) << sparkplug;
  EXPECT_TRUE(line_of(sparkplug, "commands: 0 taken, 0 refused, 0 malformed").is_object()) << sparkplug;
  EXPECT_NE(line_of(sparkplug, "connected to")["colour"], error_colour) << sparkplug;
}

}  // namespace
}  // namespace unima::test
