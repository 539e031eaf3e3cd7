// The bridge's identity on a fleet's broker (SPEC §15): the default client id from the
// host name and the machine id, and the birth message that names version, config and
// machine.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "config/mqtt_identity.hpp"
#include "mqtt/birth.hpp"

namespace unima {
namespace {

using config::default_client_id;
using config::machine_id_digits;

TEST(MachineId, TheFirstEightHexDigitsOfAMachineIdInLowerCase) {
  EXPECT_EQ(machine_id_digits("3d1219c7c4c5404aaa1f6d2a48adfda4\n"), "3d1219c7");
  EXPECT_EQ(machine_id_digits("3D1219C7C4C5404AAA1F6D2A48ADFDA4"), "3d1219c7");
}

// machine-id(5): 32 hex digits. An empty file (an image prepared for cloning, systemd's
// "uninitialized") or anything else is no machine id.
TEST(MachineId, AnythingElseIsNone) {
  EXPECT_EQ(machine_id_digits(""), "");
  EXPECT_EQ(machine_id_digits("uninitialized\n"), "");
  EXPECT_EQ(machine_id_digits("3d1219c7"), "");
  EXPECT_EQ(machine_id_digits("3d1219c7c4c5404aaa1f6d2a48adfdzz"), "");
  EXPECT_EQ(machine_id_digits("3d1219c7-c4c5-404a-aa1f-6d2a48adfda4"), "");
}

TEST(DefaultClientId, HostNameThenMachineId) {
  EXPECT_EQ(default_client_id("plc-7", "3d1219c7"), "unima-bridge-plc-7-3d1219c7");
  // Two clones: one host name, two machine ids, two sessions.
  EXPECT_NE(default_client_id("plc-7", "3d1219c7"), default_client_id("plc-7", "9a0b1c2d"));
}

TEST(DefaultClientId, WithoutAMachineIdOrAHostName) {
  EXPECT_EQ(default_client_id("plc-7", ""), "unima-bridge-plc-7");
  EXPECT_EQ(default_client_id("", "3d1219c7"), "unima-bridge-3d1219c7");
  EXPECT_EQ(default_client_id("", ""), "unima-bridge");
}

// mqtt.client_id holds 64 characters: a long host name is cut, the machine id kept whole.
TEST(DefaultClientId, ALongHostNameIsCutAndTheMachineIdKept) {
  const std::string host(80, 'h');
  const auto id = default_client_id(host, "3d1219c7");
  EXPECT_EQ(id.size(), 64u);
  EXPECT_EQ(id, "unima-bridge-" + std::string(42, 'h') + "-3d1219c7");
  EXPECT_EQ(default_client_id(host, "").size(), 64u);
}

TEST(Birth, TheDocumentOfSpec15) {
  const auto started = std::chrono::sys_days(std::chrono::year(2026) / 11 / 27) + std::chrono::hours(9) + std::chrono::minutes(36);
  const auto text = mqtt::birth_document({.version = "1.4.0",
                                          .config_sha256 = std::string(64, 'a'),
                                          .started = started,
                                          .hostname = "plc-7",
                                          .machine_id = "3d1219c7",
                                          .clock_synced = true,
                                          .config = {}});
  EXPECT_EQ(text, R"({"version":"1.4.0","config_sha256":")" + std::string(64, 'a') +
                      R"(","started":"2026-11-27T09:36:00.000000Z","hostname":"plc-7","machine_id":"3d1219c7","clock_synced":true,)"
                      R"("config":{"source":"file","number":null,"by":null,"applied_at":null,"last_result":null,"last_reason":null}})");
}

TEST(Birth, AConfigFromAfarIsNamedWithItsNumberAuthorTimeAndTheLastChange) {
  mqtt::BirthFacts facts;
  facts.config = {.source = "http", .number = 7, .by = "fleet", .applied_at = "2026-11-30T01:02:03.000000Z",
                  .last_result = "rolled_back", .last_reason = "mqtt broker not connected within 30 s"};
  const auto birth = nlohmann::json::parse(mqtt::birth_document(facts));
  EXPECT_EQ(birth["config"], nlohmann::json::parse(R"({"source":"http","number":7,"by":"fleet",)"
                                                   R"("applied_at":"2026-11-30T01:02:03.000000Z","last_result":"rolled_back",)"
                                                   R"("last_reason":"mqtt broker not connected within 30 s"})"))
      << birth.dump();
}

TEST(Birth, NoMachineIdIsNull) {
  mqtt::BirthFacts facts;
  facts.version = "1";
  facts.hostname = "plc-7";
  const auto birth = nlohmann::json::parse(mqtt::birth_document(facts));
  EXPECT_TRUE(birth["machine_id"].is_null()) << birth.dump();
  EXPECT_EQ(birth["clock_synced"], false);
}

}  // namespace
}  // namespace unima
