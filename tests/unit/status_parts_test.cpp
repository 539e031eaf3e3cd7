// The typed parts of the status document (issue 38): each reads the daemon's own
// document (tests/golden/status_*.json, kept by the integration test StatusKeys with every
// part on) and writes it back exactly — every key, null and number type — so the JSON of
// /api/status and `status --json` is what it was before the status was typed.

#include <gtest/gtest.h>

#include <filesystem>

#include <nlohmann/json.hpp>

#include "master/gateway_status.hpp"
#include "monitor/monitor_status.hpp"
#include "mqtt/mqtt_status.hpp"
#include "remote/config_status.hpp"
#include "sparkplug/edge_status.hpp"
#include "state/state_status.hpp"
#include "status/activity.hpp"
#include "status/bridge_status.hpp"
#include "status/document.hpp"
#include "status/line_status.hpp"
#include "status/port_status.hpp"
#include "tests/support/temp_files.hpp"
#include "unimabus/bus_status.hpp"
#include "web/login_status.hpp"

namespace unima {
namespace {

nlohmann::json golden(const std::string& name) {
  return nlohmann::json::parse(
      test_support::read_file(std::filesystem::path(UNIMA_SOURCE_DIR) / "tests" / "golden" / ("status_" + name + ".json")));
}

template <class Part>
void expect_round_trip(const nlohmann::json& part) {
  ASSERT_FALSE(part.is_null());
  EXPECT_EQ(nlohmann::json(part.get<Part>()), part);
}

// The bridge's own part is the document's top level: what no service wrote. A key the
// daemon adds there without a field in BridgeStatus fails here.
void expect_bridge_round_trip(const nlohmann::json& document) {
  auto own = document;
  for (const auto* service_key : {"ports", "devices", "modules", "unimabus", "modbus", "indicators", "monitor", "state", "mqtt",
                                  "sparkplug", "http", "master", "gateway", "lines", "config_in_force"})
    own.erase(service_key);
  ASSERT_TRUE(own.contains("uptime_s"));
  EXPECT_EQ(nlohmann::json(document.get<status::BridgeStatus>()), own);
}

// The parts every document holds, whatever the mode: the bridge's own, the UnimaBUS side, the monitor's.
void expect_common_round_trips(const nlohmann::json& s) {
  expect_bridge_round_trip(s);
  expect_round_trip<remote::ConfigStatus>(s["config_in_force"]);
  expect_round_trip<unimabus::UnimabusStatus>(s["unimabus"]);
  ASSERT_EQ(s["devices"].size(), 4u);
  for (const auto& device : s["devices"]) expect_round_trip<unimabus::DeviceStatus>(device);
  ASSERT_EQ(s["modules"].size(), 7u);
  for (const auto& module : s["modules"]) expect_round_trip<unimabus::ModuleStatus>(module);
  expect_round_trip<status::Activity>(s["modbus"]);
  for (const auto& indicator : s["indicators"]) expect_round_trip<monitor::IndicatorStatus>(indicator);
  expect_round_trip<monitor::MonitorStatus>(s["monitor"]);
}

TEST(StatusParts, TheSlavesPartsReadAndWriteTheDocumentExactly) {
  const auto s = golden("slave");
  expect_common_round_trips(s);
  ASSERT_EQ(s["indicators"].size(), 1u);
  expect_round_trip<state::StateStatus>(s["state"]);
  expect_round_trip<mqtt::MqttStatus>(s["mqtt"]);
  expect_round_trip<sparkplug::EdgeStatus>(s["sparkplug"]);
  expect_round_trip<web::LoginStatus>(s["http"]["logins"]);
  expect_round_trip<status::HandshakeStatus>(s["http"]["handshakes"]);
  ASSERT_EQ(s["ports"].size(), 2u);
  for (const auto& port : s["ports"]) expect_round_trip<status::PortStatus>(port);
}

TEST(StatusParts, TheMastersPartsReadAndWriteTheDocumentExactly) {
  const auto s = golden("master");
  expect_common_round_trips(s);
  for (const auto& port : s["ports"]) expect_round_trip<status::PortStatus>(port);
  for (const auto& device : s["master"]) expect_round_trip<master::MasterDeviceStatus>(device);
  expect_round_trip<master::GatewayStatus>(s["gateway"]);
  ASSERT_FALSE(s["gateway"]["units"].empty());
  ASSERT_EQ(s["lines"].size(), 1u) << "modbus.rtu, the master's line";
  expect_round_trip<status::LineStatus>(s["lines"][0]);
}

// The whole document, as the services fill it and /metrics, the CLI and the page read it,
// is the JSON of before: every part where it was, and no key more.
TEST(StatusParts, TheWholeDocumentReadsAndWritesBothModesExactly) {
  for (const std::string mode : {"slave", "master"}) {
    const auto s = golden(mode);
    EXPECT_EQ(nlohmann::json(s.get<status::Document>()), s) << mode;
  }
}

// A part that is off has no key at all, "http" included, and "ports" is always a list.
TEST(StatusParts, APartThatIsOffHasNoKey) {
  status::Document document;
  document.bridge = status::BridgeStatus{};
  const nlohmann::json bare = document;
  EXPECT_TRUE(bare["ports"].is_array());
  for (const auto* key : {"modbus", "indicators", "monitor", "unimabus", "devices", "modules", "master", "gateway", "state", "mqtt",
                          "sparkplug", "http"})
    EXPECT_FALSE(bare.contains(key)) << key;
  document.http.logins = web::LoginStatus{};
  const nlohmann::json with_users = document;
  EXPECT_TRUE(with_users["http"].contains("logins"));
  EXPECT_FALSE(with_users["http"].contains("handshakes"));
  const auto read_back = with_users.get<status::Document>();
  EXPECT_TRUE(read_back.http.logins.has_value());
  EXPECT_FALSE(read_back.mqtt.has_value());
}

// The parts' empty forms as the daemon writes them: no state file, no buffer, no primary host.
TEST(StatusParts, WhatIsOffIsNullAndWhatIsNotCountedIsLeftOut) {
  EXPECT_EQ(nlohmann::json(state::StateStatus{}), nlohmann::json::parse(R"({"file": null})"));
  const nlohmann::json mqtt = mqtt::MqttStatus{};
  EXPECT_TRUE(mqtt["buffer"].is_null());
  EXPECT_TRUE(mqtt["last_takeover"].is_null());
  const nlohmann::json edge = sparkplug::EdgeStatus{};
  EXPECT_TRUE(edge["primary_host"].is_null());
  EXPECT_TRUE(edge["bdSeq"].is_null());
  const nlohmann::json port = status::PortStatus{"rtu", 0, {{"Done", 0}}, {}, {}, {}};
  EXPECT_EQ(port, nlohmann::json::parse(R"({"port": "rtu", "transactions": 0, "Done": 0})"));
  EXPECT_EQ(nlohmann::json(unimabus::DeviceStatus{"D2", {}, {}, false, {}}),
            nlohmann::json::parse(R"({"bank": "D2", "type": null, "online": false})"));
  const nlohmann::json sim = unimabus::UnimabusStatus{{}, "sim", {}, 0, 0, {}};
  EXPECT_FALSE(sim.contains("clients")) << sim;
  EXPECT_TRUE(sim["recording"].is_null()) << sim;
  const nlohmann::json bridge = status::BridgeStatus{};
  EXPECT_FALSE(bridge.contains("rss_bytes")) << bridge;
  const nlohmann::json unseen = monitor::IndicatorStatus{1, 0x100, {}, {}, {}};
  EXPECT_EQ(unseen, nlohmann::json::parse(R"({"address": 1, "register": 256, "value": null, "access": null, "time": null})"));
}

// An LED (SPEC §8) is lit from its last frame for `lit` and no longer; without a frame it
// is dark and says so (null), never "0 ms ago".
TEST(StatusParts, AnLedIsLitForItsTimeAfterTheLastFrame) {
  using std::chrono::milliseconds;
  const auto lit = status::activity(milliseconds(50), 7, milliseconds(50));
  EXPECT_TRUE(lit.active);
  EXPECT_EQ(lit.last_ms_ago, 50);
  EXPECT_EQ(lit.frames, 7u);
  EXPECT_EQ(lit.lit_ms, 50);
  EXPECT_FALSE(status::activity(milliseconds(51), 7, milliseconds(50)).active);
  const auto dark = status::activity(std::nullopt, 0, milliseconds(100));
  EXPECT_FALSE(dark.active);
  EXPECT_TRUE(nlohmann::json(dark)["last_ms_ago"].is_null());
}

}  // namespace
}  // namespace unima
