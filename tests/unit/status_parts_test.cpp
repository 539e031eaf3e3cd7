// The typed parts of the status document (issue 38): each reads the daemon's own
// document (tests/golden/status_*.json, kept by the integration test StatusKeys with every
// part on) and writes it back exactly — every key, null and number type — so the JSON of
// /api/status and `status --json` is what it was before the status was typed.

#include <gtest/gtest.h>

#include <filesystem>

#include <nlohmann/json.hpp>

#include "master/gateway_status.hpp"
#include "mqtt/mqtt_status.hpp"
#include "sparkplug/edge_status.hpp"
#include "state/state_status.hpp"
#include "status/port_status.hpp"
#include "tests/support/temp_files.hpp"
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

TEST(StatusParts, TheSlavesPartsReadAndWriteTheDocumentExactly) {
  const auto s = golden("slave");
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
  for (const auto& port : s["ports"]) expect_round_trip<status::PortStatus>(port);
  for (const auto& device : s["master"]) expect_round_trip<master::MasterDeviceStatus>(device);
  expect_round_trip<master::GatewayStatus>(s["gateway"]);
  ASSERT_FALSE(s["gateway"]["units"].empty());
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
}

}  // namespace
}  // namespace unima
