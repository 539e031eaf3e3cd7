// remote_config (SPEC §19): its defaults and bounds, the channels it may open only with the
// sections they need, each error at its file:line:column; and check/'s rule that every
// user it lets PUT a config is in the http.users file, as `unima-bridge check` and the
// daemon's remote changes both ask it.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "check/check_config.hpp"
#include "config/config.hpp"
#include "tests/support/config_parse_error.hpp"
#include "tests/support/error_message.hpp"
#include "tests/support/temp_files.hpp"

namespace unima::config {
namespace {

using namespace std::chrono_literals;

Config parse_remote(const std::string& text) { return parse_text(text, "bridge.yaml", Host{}); }

std::string remote_error(const std::string& text) { return test_support::config_parse_error(text); }

// An mqtt section that needs no warning of its own (a client id: Host{} has no machine id).
const std::string mqtt_section = "mqtt: { broker: 'mqtt://127.0.0.1', client_id: site-17 }\n";

TEST(RemoteConfigSection, AbsentIsNoneAndAnEmptySectionTakesTheDefaults) {
  EXPECT_FALSE(parse_remote(mqtt_section).remote_config) << "without the section: the CLI alone changes the config";

  const auto c = parse_remote(mqtt_section + "remote_config: {}\n");
  ASSERT_TRUE(c.remote_config);
  EXPECT_FALSE(c.remote_config->mqtt);
  EXPECT_TRUE(c.remote_config->http.empty());
  EXPECT_EQ(c.remote_config->probe, 30s);
  EXPECT_EQ(c.remote_config->keep, 10u);
  EXPECT_EQ(c.remote_config->origin, "bridge.yaml:2:16");
  EXPECT_EQ(c.remote_config->http_origin, "bridge.yaml:2:16") << "no http key: the section's position";
}

TEST(RemoteConfigSection, EveryKeyAsWritten) {
  const auto c = parse_remote(mqtt_section +
                               "http: { listen: 127.0.0.1, users: /etc/unima-bridge/http.users }\n"
                               "remote_config:\n"
                               "  mqtt: true\n"
                               "  http: [alice, bob]\n"
                               "  probe: 2m\n"
                               "  keep: 25\n");
  ASSERT_TRUE(c.remote_config);
  EXPECT_TRUE(c.remote_config->mqtt);
  EXPECT_EQ(c.remote_config->http, (std::vector<std::string>{"alice", "bob"}));
  EXPECT_EQ(c.remote_config->probe, 120s);
  EXPECT_EQ(c.remote_config->keep, 25u);
  EXPECT_EQ(c.remote_config->origin, "bridge.yaml:4:3") << "a block mapping is where its first key is";
  EXPECT_EQ(c.remote_config->http_origin, "bridge.yaml:5:9");
  EXPECT_TRUE(warnings(c).empty()) << "HTTP on loopback: a PUT is allowed there";
}

TEST(RemoteConfigSection, ProbeIsADurationFromOneSecondToTenMinutes) {
  const auto probe = [](const std::string& written) {
    return parse_remote("remote_config:\n  probe: " + written + "\n").remote_config->probe;
  };
  EXPECT_EQ(probe("1s"), 1s);
  EXPECT_EQ(probe("1000ms"), 1s);
  EXPECT_EQ(probe("10m"), 10min);
  EXPECT_EQ(probe("600s"), 10min);
  EXPECT_EQ(remote_error("remote_config:\n  probe: 999ms\n"),
            "bridge.yaml:2:10: remote_config.probe must be 1s..10m (written: 999ms)");
  EXPECT_EQ(remote_error("remote_config:\n  probe: 601s\n"),
            "bridge.yaml:2:10: remote_config.probe must be 1s..10m (written: 601s)");
  EXPECT_EQ(remote_error("remote_config:\n  probe: 30\n"),
            "bridge.yaml:2:10: '30' is not a duration (write e.g. 200ms, 1s, 5m)");
}

TEST(RemoteConfigSection, KeepIsOneToAThousand) {
  EXPECT_EQ(parse_remote("remote_config: { keep: 1 }\n").remote_config->keep, 1u);
  EXPECT_EQ(parse_remote("remote_config: { keep: 1000 }\n").remote_config->keep, 1000u);
  for (const char* written : {"0", "1001"})
    EXPECT_EQ(remote_error(std::string("remote_config:\n  keep: ") + written + "\n"),
              "bridge.yaml:2:9: remote_config.keep must be 1..1000 (applied configs kept in the state directory)");
  EXPECT_EQ(remote_error("remote_config:\n  keep: ten\n"), "bridge.yaml:2:9: 'ten' is not a number (write decimal or 0x hex)");
}

TEST(RemoteConfigSection, EachErrorNamesItsKeyAtItsPosition) {
  EXPECT_EQ(remote_error("remote_config:\n  mqtt: true\n"),
            "bridge.yaml:2:9: remote_config.mqtt: true takes configs on <mqtt.topic>/config/set, but there is no mqtt "
            "section: add mqtt, or set remote_config.mqtt to false");
  EXPECT_EQ(remote_error("remote_config:\n  mqtt: false\n"), "(no error)") << "off needs no broker";
  EXPECT_EQ(remote_error("remote_config:\n  http: [alice]\n"),
            "bridge.yaml:2:9: remote_config.http names users who may PUT /api/config, but there is no http section: "
            "add http with tls and users, or take remote_config.http out");
  EXPECT_EQ(remote_error("http: { port: 8080 }\nremote_config:\n  http: [alice]\n"),
            "bridge.yaml:3:9: remote_config.http names users who may PUT /api/config, but http has no users file: set "
            "http.users, or take remote_config.http out");
  EXPECT_EQ(remote_error("remote_config:\n  http: []\n"), "(no error)") << "no user: no http needed";
  EXPECT_EQ(remote_error("http: { users: /etc/u }\nremote_config:\n  http: [alice, bob, alice]\n"),
            "bridge.yaml:3:22: remote_config.http: 'alice' is listed twice");
  EXPECT_EQ(remote_error("http: { users: /etc/u }\nremote_config:\n  http: alice\n"),
            "bridge.yaml:3:9: remote_config.http must be a list of user names of http.users, e.g. [alice]");
  EXPECT_EQ(remote_error("http: { users: /etc/u }\nremote_config:\n  http: ['a:b']\n"),
            "bridge.yaml:3:10: remote_config.http: a user name is not empty and has no ':' (as in http.users)");
  EXPECT_EQ(remote_error("remote_config:\n  mqtt: maybe\n"), "bridge.yaml:2:9: 'maybe' is not a boolean (true or false)");
  EXPECT_EQ(remote_error("remote_config:\n  mqt: true\n"),
            "bridge.yaml:2:3: unknown key 'mqt' in remote_config (known: mqtt, http, probe, keep)");
}

TEST(RemoteConfigSection, UsersOverPlainHttpBeyondLoopbackAreAllowedWithAWarning) {
  const auto c = parse_remote("http: { listen: 0.0.0.0, users: /etc/u }\nremote_config:\n  http: [alice]\n");
  const auto warned = warnings(c);  // http's own warning of passwords in clear, and this one
  EXPECT_NE(std::find(warned.begin(), warned.end(),
                      "bridge.yaml:3:9: warning: remote_config.http: http listens on 0.0.0.0 without tls, and a PUT "
                      "/api/config over plain HTTP is refused from anywhere but loopback; set http.tls for these users "
                      "to change the config from afar"),
            warned.end())
      << ::testing::PrintToString(warned);
  const auto with_tls = parse_remote(
      "http: { listen: 0.0.0.0, users: /etc/u, tls: { certificate: /etc/c.pem, key: /etc/c.key } }\n"
      "remote_config:\n  http: [alice]\n");
  EXPECT_TRUE(warnings(with_tls).empty());
  const auto on_loopback = parse_remote("http: { listen: '::1', users: /etc/u }\nremote_config:\n  http: [alice]\n");
  EXPECT_TRUE(warnings(on_loopback).empty());
}

// openssl passwd -6 -salt salzsalz secret
const std::string admin_line =
    "admin:$6$salzsalz$T6JPgc5oSlQmLkWq.mzSbtz8riZYp5RKogAdkAMphpHutqbzTWM.R2hHZXzRwqaHTGPbckcwMimHDhrrzvUs40\n";

TEST(CheckConfig, EveryRemoteHttpUserMustBeInTheUsersFile) {
  test_support::TempDir dir;
  const auto users = (dir.path() / "http.users").string();
  test_support::write_file(users, admin_line);
  const auto check_error = [&](const std::string& listed) {
    const auto config = parse_remote("http: { users: " + users + " }\nremote_config:\n  http: " + listed + "\n");
    return test_support::error_message<std::runtime_error>([&] { check::check_config(config); });
  };
  EXPECT_EQ(check_error("[admin]"), "(no error)");
  EXPECT_EQ(check_error("[admin, ghost]"),
            "bridge.yaml:3:9: remote_config.http: 'ghost' is not a user of http.users (" + users +
                "): add the user to that file, or take the name out of the list");
  // The users file's own errors as the daemon says them, before its users are looked at.
  test_support::write_file(users, "admin\n");
  EXPECT_EQ(check_error("[admin]"), "bridge.yaml:1:16: http.users " + users + ":1: expected name:password-hash");
}

TEST(CheckConfig, WhatTheDaemonWouldRefuseAtStartIsRefused) {
  // A deadband naming a value its bank does not have: the value model's error, at its key.
  const auto config = parse_remote("devices: { D1: { type: unigen-chp, address: 5 } }\n"
                                    "report: { deadband: { D1.no_such_value: 5 } }\n");
  const auto message = test_support::error_message<std::runtime_error>([&] { check::check_config(config); });
  EXPECT_EQ(message.rfind("bridge.yaml:2:23: report.deadband.D1.no_such_value", 0), 0u) << message;
  EXPECT_EQ(test_support::error_message<std::runtime_error>([&] { check::check_config(parse_remote("")); }),
            "(no error)");
}

}  // namespace
}  // namespace unima::config
