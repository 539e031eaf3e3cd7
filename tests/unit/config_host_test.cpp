// The config's parse is pure (parse_text: no file opened, nothing looked at on disk, the
// host's name and environment handed in as Host); what the config names on this machine is
// looked at by check_on_host, which `unima-bridge check`, the daemon's start and a reload
// share through load_file. Its errors name the key's file:line:column as the parse's do.

#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <string>

#include "config/config.hpp"
#include "tests/support/error_message.hpp"
#include "tests/support/temp_files.hpp"

namespace unima::config {
namespace {

using test_support::TempDir;

/// A machine called `name` whose environment holds `variables` only.
Host host_called(std::string name, std::map<std::string, std::string, std::less<>> variables = {}) {
  Host host;
  host.name = std::move(name);
  host.environment = [variables = std::move(variables)](std::string_view variable) {
    const auto found = variables.find(variable);
    return found == variables.end() ? std::string() : found->second;
  };
  return host;
}

std::string host_error(Config& config) {
  return test_support::error_message<ConfigError>([&] { check_on_host(config); });
}

constexpr const char* one_telegram = "{\"t\":0,\"addr\":5,\"slot\":0,\"offset\":1,\"values\":[7]}\n";

TEST(ConfigParse, AMissingRecordingParsesAndTheHostCheckNamesIt) {
  auto config = parse_text("unimabus:\n  transport: replay\n  file: /nonexistent/recording.jsonl\n", "cfg.yaml",
                           host_called("plc-7"));
  EXPECT_EQ(config.unimabus.replay.file, "/nonexistent/recording.jsonl");
  EXPECT_EQ(config.unimabus.replay.file_origin, "cfg.yaml:3:9");
  EXPECT_FALSE(config.unimabus.replay.recording);
  EXPECT_TRUE(host_error(config).starts_with("cfg.yaml:3:9: cannot read the recording /nonexistent/recording.jsonl: "))
      << host_error(config);
}

TEST(ConfigHostCheck, ReadsTheRecordingIntoTheConfig) {
  TempDir dir;
  const auto file = (dir.path() / "rec.jsonl").string();
  test_support::write_file(file, one_telegram);
  auto config = parse_text("unimabus: { transport: replay, file: " + file + " }\n", "cfg.yaml", host_called("plc-7"));
  check_on_host(config);
  ASSERT_TRUE(config.unimabus.replay.recording);
  ASSERT_EQ(config.unimabus.replay.recording->entries.size(), 1u);

  test_support::write_file(file, std::string(one_telegram) + "not json\n");
  auto bad = parse_text("unimabus: { transport: replay, file: " + file + " }\n", "cfg.yaml", host_called("plc-7"));
  EXPECT_TRUE(host_error(bad).starts_with(file + ":2: ")) << host_error(bad);  // the recording's own line
}

TEST(ConfigParse, NotesThePathsTheHostCheckLooksAtWithTheirPositions) {
  const auto config = parse_text(
      "unimabus:\n"
      "  transport: feed\n"
      "  listen: unix:/run/x/feed.sock\n"
      "  record: { file: /var/log/x/rec.jsonl }\n"
      "monitor:\n"
      "  file: /var/log/x/monitor.log\n",
      "bridge.yaml", host_called("plc-7"));
  ASSERT_EQ(config.host_paths.size(), 5u);
  const auto expect = [&](std::size_t n, HostPath::Use use, const char* key, const char* path, const char* origin) {
    EXPECT_EQ(config.host_paths[n].use, use) << n;
    EXPECT_EQ(config.host_paths[n].key, key) << n;
    EXPECT_EQ(config.host_paths[n].path, path) << n;
    EXPECT_EQ(config.host_paths[n].origin, origin) << n;
  };
  expect(0, HostPath::Use::log_file, "unimabus.record.file", "/var/log/x/rec.jsonl", "bridge.yaml:4:19");
  expect(1, HostPath::Use::unix_socket, "unimabus.listen", "/run/x/feed.sock", "bridge.yaml:3:11");
  expect(2, HostPath::Use::log_file, "monitor.file", "/var/log/x/monitor.log", "bridge.yaml:6:9");
  // status.socket's default is where the daemon listens when the file does not say: the
  // message points at the file's first section.
  expect(3, HostPath::Use::unix_socket, "status.socket", "/run/unima-bridge/control.sock", "bridge.yaml:1:1");
  // So is the state file's default, beside the config.
  expect(4, HostPath::Use::state_file, "state.file", "bridge.state", "bridge.yaml:1:1");
}

TEST(ConfigHostCheck, ARegularFileWhereASocketGoesParsesAndIsRefusedOnTheHost) {
  TempDir dir;
  const auto file = (dir.path() / "control.sock").string();
  test_support::write_file(file, "precious");
  auto config = parse_text("log: { level: info }\nstatus:\n  socket: " + file + "\n", "bridge.yaml", host_called("x"));
  EXPECT_EQ(host_error(config), "bridge.yaml:3:11: status.socket: " + file +
                                    " names a regular file, not a socket; the daemon never removes it to listen there");
  EXPECT_EQ(test_support::read_file(file), "precious");
}

TEST(ConfigHostCheck, AcceptsWhatIsFreeOrASocket) {
  TempDir dir;
  auto config = parse_text("status:\n  socket: " + (dir.path() / "control.sock").string() + "\nmonitor:\n  file: " +
                               (dir.path() / "monitor.log").string() + "\n",
                           "bridge.yaml", host_called("x"));
  EXPECT_NO_THROW(check_on_host(config));
}

// Issue 44, finding 2: `check` accepted what the daemon refused or did silently. A
// password file that cannot be read is an error at its key; a state, buffer or monitor
// file in a directory that is not there is a warning (the daemon makes the directory).
TEST(ConfigHostCheck, AMissingPasswordFileIsAnErrorAtItsKey) {
  TempDir dir;
  const auto missing = (dir.path() / "mqtt.pass").string();
  auto config = parse_text("mqtt:\n  broker: 'mqtt://127.0.0.1'\n  username: site\n  password_file: " + missing + "\n",
                           "bridge.yaml", host_called("x"));
  EXPECT_EQ(host_error(config),
            "bridge.yaml:4:18: mqtt.password_file: " + missing + ": no such file: correct the path, or put the file there");
  test_support::write_file(missing, "secret\n");
  EXPECT_NO_THROW(check_on_host(config));
}

TEST(ConfigHostCheck, AFileInADirectoryThatIsNotThereIsAWarningAtItsKey) {
  TempDir dir;
  const auto typo = (dir.path() / "unima-brige").string();
  auto config = parse_text("state:\n  file: " + typo + "/state\nmonitor:\n  file: " + typo + "/monitor.log\n",
                           "bridge.yaml", host_called("x"));
  check_on_host(config);
  const auto why = ": the directory " + typo + " is not there; the daemon makes it at start: correct the path if it is mistyped";
  EXPECT_EQ(warnings(config), (std::vector<std::string>{
                                  "bridge.yaml:4:9: warning: monitor.file: " + typo + "/monitor.log" + why,
                                  "bridge.yaml:2:9: warning: state.file: " + typo + "/state" + why,
                              }));
}

TEST(ConfigParse, TheHostNameAndMachineIdGiveTheDefaultMqttClient) {
  auto host = host_called("plc-7");
  host.machine_id = "3d1219c7";
  const auto named = parse_text("mqtt: { broker: 'mqtt://10.0.0.2' }\n", "m.yaml", host);
  ASSERT_TRUE(named.mqtt);
  EXPECT_EQ(named.mqtt->client_id, "unima-bridge-plc-7-3d1219c7");
  EXPECT_EQ(named.mqtt->topic, "unima/unima-bridge-plc-7-3d1219c7");
  EXPECT_EQ(named.mqtt->host_name, "plc-7");
  EXPECT_EQ(named.mqtt->machine_id, "3d1219c7");
  EXPECT_EQ(warnings(named), std::vector<std::string>{});
  const auto set = parse_text("mqtt: { broker: 'mqtt://10.0.0.2', client_id: site-17 }\n", "m.yaml", host);
  EXPECT_EQ(set.mqtt->client_id, "site-17");
}

// No machine id: the host name alone, and a warning that cloned images would collide —
// but none when the config names its client id (then the default does not matter).
TEST(ConfigParse, WithoutAMachineIdTheDefaultClientIsTheHostNameAndAWarningSaysSo) {
  const auto named = parse_text("mqtt: { broker: 'mqtt://10.0.0.2' }\n", "m.yaml", host_called("plc-7"));
  EXPECT_EQ(named.mqtt->client_id, "unima-bridge-plc-7");
  EXPECT_EQ(warnings(named),
            std::vector<std::string>{
                "m.yaml:1:7: warning: mqtt.client_id: this machine has no /etc/machine-id (machine-id(5)), so the default "
                "client id is unima-bridge-plc-7 without one: bridges of one cloned image would share it and take the "
                "broker's session from each other; set mqtt.client_id"});
  const auto nameless = parse_text("mqtt: { broker: 'mqtt://10.0.0.2' }\n", "m.yaml", host_called(""));
  EXPECT_EQ(nameless.mqtt->client_id, "unima-bridge");
  const auto set = parse_text("mqtt: { broker: 'mqtt://10.0.0.2', client_id: site-17 }\n", "m.yaml", host_called("plc-7"));
  EXPECT_EQ(warnings(set), std::vector<std::string>{});
}

// Read once from the file machine-id(5) names (a test's own file here); a file that is
// not a machine id counts as none.
TEST(ConfigHostCheck, TheMachineIdIsReadFromItsFile) {
  TempDir dir;
  test_support::write_file(dir.path() / "machine-id", "3D1219C7C4C5404AAA1F6D2A48ADFDA4\n");
  EXPECT_EQ(Host::this_machine((dir.path() / "machine-id").string()).machine_id, "3d1219c7");
  test_support::write_file(dir.path() / "empty", "");
  EXPECT_EQ(Host::this_machine((dir.path() / "empty").string()).machine_id, "");
  EXPECT_EQ(Host::this_machine((dir.path() / "none").string()).machine_id, "");
}

// SPEC §15: config_sha256 is of the file's bytes, as sha256sum prints it.
TEST(ConfigParse, TheConfigsDigestIsOfItsText) {
  EXPECT_EQ(parse_text("", "empty.yaml", host_called("x")).file_sha256,
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(parse_text("log: { level: info }\n", "l.yaml", host_called("x")).file_sha256,
            "c24ecf020b550feddc3a5b9c41e0273a38b717d3690b800bd2841d7ce3963ac2");
}

TEST(ConfigParse, TheStateFileFollowsTheEnvironmentGiven) {
  const auto service = parse_text("", "/etc/unima/bridge.yaml",
                                  host_called("x", {{"STATE_DIRECTORY", "/var/lib/unima-bridge:/var/lib/other"}}));
  EXPECT_EQ(service.state.file, "/var/lib/unima-bridge/state");
  const auto by_hand = parse_text("", "/etc/unima/bridge.yaml", host_called("x"));
  EXPECT_EQ(by_hand.state.file, "/etc/unima/bridge.state");
  const auto set = parse_text("state: { file: /srv/s }\n", "/etc/unima/bridge.yaml",
                              host_called("x", {{"STATE_DIRECTORY", "/var/lib/unima-bridge"}}));
  EXPECT_EQ(set.state.file, "/srv/s");
}

TEST(ConfigParse, TheMqttBufferGoesWhereTheStateGoesUnlessGivenOrNone) {
  const auto mqtt = std::string("mqtt: { broker: 'mqtt://10.0.0.2' }\n");
  const auto service = parse_text(mqtt, "/etc/unima/bridge.yaml", host_called("x", {{"STATE_DIRECTORY", "/var/lib/unima-bridge"}}));
  EXPECT_EQ(service.mqtt->buffer.file, "/var/lib/unima-bridge/mqtt-buffer");
  EXPECT_EQ(service.mqtt->buffer.max_size, 64u << 20);
  const auto by_hand = parse_text(mqtt, "/etc/unima/bridge.yaml", host_called("x"));
  EXPECT_EQ(by_hand.mqtt->buffer.file, "/etc/unima/bridge.mqtt-buffer");
  const auto& noted = by_hand.host_paths.back();
  EXPECT_EQ(noted.use, HostPath::Use::state_file);
  EXPECT_EQ(noted.key, "mqtt.buffer.file");
  EXPECT_EQ(noted.origin, "/etc/unima/bridge.yaml:1:7");
  const auto set = parse_text("mqtt: { broker: 'mqtt://x', buffer: { file: /srv/h, max_size: 1MiB } }\n", "b.yaml", host_called("x"));
  EXPECT_EQ(set.mqtt->buffer.file, "/srv/h");
  EXPECT_EQ(set.mqtt->buffer.max_size, 1u << 20);
  EXPECT_EQ(set.host_paths.back().origin, "b.yaml:1:45");
  const auto off = parse_text("mqtt: { broker: 'mqtt://x', buffer: { file: none } }\n", "b.yaml", host_called("x"));
  EXPECT_EQ(off.mqtt->buffer.file, "");
  EXPECT_NE(off.host_paths.back().key, "mqtt.buffer.file");
}

TEST(ConfigParse, MqttBufferErrorsPointAtTheKey) {
  const auto error = [](const std::string& yaml) {
    return test_support::error_message<ConfigError>([&] { (void)parse_text(yaml, "cfg.yaml", host_called("x")); });
  };
  EXPECT_EQ(error("mqtt: { broker: 'mqtt://x', buffer: { max_size: 64 } }\n"), "cfg.yaml:1:49: 64 is out of range 4096..1099511627776 bytes");
  EXPECT_EQ(error("mqtt: { broker: 'mqtt://x', buffer: { max_size: 64 parsecs } }\n"),
            "cfg.yaml:1:49: '64 parsecs' is not a size (write e.g. 65536, 64k, 10MB)");
  EXPECT_EQ(error("mqtt: { broker: 'mqtt://x', buffer: { file: '' } }\n"),
            "cfg.yaml:1:45: mqtt.buffer.file must be a path, or none to keep no history");
  EXPECT_EQ(error("mqtt: { broker: 'mqtt://x', buffer: { size: 1M } }\n"),
            "cfg.yaml:1:39: unknown key 'size' in mqtt.buffer (known: file, max_size)");
  EXPECT_EQ(error("mqtt: { broker: 'mqtt://x', buffer: 64MiB }\n"),
            "cfg.yaml:1:37: mqtt.buffer must be a mapping, e.g. { file: /var/lib/unima-bridge/mqtt-buffer, max_size: 64MiB }");
  EXPECT_EQ(error("state: { file: /srv/s }\nmqtt: { broker: 'mqtt://x', buffer: { file: /srv/s } }\n"),
            "cfg.yaml:2:45: mqtt.buffer.file is the state file; each needs a file of its own");
}

TEST(ConfigLoad, LoadTextIsTheParseAndTheHostCheck) {
  TempDir dir;
  const auto file = (dir.path() / "rec.jsonl").string();
  test_support::write_file(file, one_telegram);
  const auto config = load_text("unimabus: { transport: replay, file: " + file + " }\n", "cfg.yaml", host_called("x"));
  EXPECT_TRUE(config.unimabus.replay.recording);
  EXPECT_TRUE(test_support::error_message<ConfigError>([&] {
                (void)load_text("unimabus: { transport: replay, file: " + file + ".gone }\n", "cfg.yaml");
              }).starts_with("cfg.yaml:1:38: cannot read the recording "));
}

}  // namespace
}  // namespace unima::config
