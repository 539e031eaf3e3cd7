// The page's Config box (SPEC §19 "Seen", issue 40) in headless Chromium against the real
// daemon over HTTPS with http.users: a user whom remote_config.http lists applies a file
// through the box's form — the Modbus TCP port moves, the box shows the config from http by
// that user, the history and the diff of the changed line — sees a file with errors refused
// at its line and column with nothing changed, and goes back to the operator's file; a user
// it does not list sees which config is in force and its history, but neither the form nor
// the text (a config may hold passwords).

#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/integration/certificate_fixture.hpp"

namespace unima::test {
namespace {

constexpr auto page_good_colour = "rgb(31, 157, 69)";  // panel.css --on
constexpr auto page_bad_colour = "rgb(210, 47, 47)";   // panel.css --err

class PageConfig : public CertificateTest {
 protected:
  void SetUp() override {
    CertificateTest::SetUp();
    users = dir.path() / "http-users";
    add_user("fleet", "fleet-pass");
    add_user("technician", "tech-pass");
    http_port = free_port();
    config.extra += "http: { listen: 127.0.0.1, port: " + std::to_string(http_port) + ", users: " + users.string() +
                    ", tls: { certificate: " + pem("server.pem") + ", key: " + pem("server.key") + " } }\n" +
                    "remote_config: { http: [fleet], probe: 1s }\n";
    start();
    ASSERT_TRUE(wait_for_port(http_port)) << daemon->log();
  }

  void add_user(const std::string& name, const std::string& password) {
    const auto hashed = run("openssl passwd -6 '" + password + "'");
    ASSERT_EQ(hashed.status, 0) << hashed.output;
    std::ofstream(users, std::ios::app) << name << ":" << hashed.output;
  }

  /// `yaml` in a file of the test's directory, for the page's file chooser.
  std::string file_with(const std::string& name, const std::string& yaml) const {
    const auto path = dir.path() / name;
    std::ofstream(path) << yaml;
    return path.string();
  }

  /// The page opened as `credentials` ("name:password"), its Config box once loaded, and the
  /// `steps` (--apply-file F, --revert) done through it; the driver's JSON line.
  nlohmann::json page_config(const std::string& credentials, const std::string& steps = "") const {
    const auto command = std::string(UNIMA_SOURCE_DIR) + "/tests/integration/browser/page_in_chromium.py --url https://" +
                         credentials + "@127.0.0.1:" + std::to_string(http_port) +
                         "/ --ignore-certificate-errors --config-box --timeout 30 " + steps + " 2>&1";
    const auto result = run(command);
    EXPECT_EQ(result.status, 0) << result.output << daemon->log();
    const auto at = result.output.rfind("{\"ok\"");
    if (at == std::string::npos) return {};
    return nlohmann::json::parse(result.output.substr(at), nullptr, false);
  }

  bool serves_on(std::uint16_t port) const {
    ModbusClient client(port);
    return client.read_holding(0x0100, 1).has_value();
  }

  std::filesystem::path users;
  std::uint16_t http_port = 0;
};

/// The box's line of `field` ("in-force", "last").
nlohmann::json config_line(const nlohmann::json& box, const std::string& field) {
  for (const auto& line : box["lines"])
    if (line["field"] == field) return line;
  return {};
}

/// Whether the box's diff has a line of `kind` ("-", "+") that is exactly `text`.
bool diff_has(const nlohmann::json& box, const std::string& kind, const std::string& text) {
  for (const auto& line : box["diff"]["lines"])
    if (line["kind"] == kind && line["text"] == kind + text) return true;
  return false;
}

std::string port_line(std::uint16_t port) { return "  tcp: { listen: 127.0.0.1, port: " + std::to_string(port) + " }"; }

TEST_F(PageConfig, AListedUserAppliesAFileThroughThePageSeesTheDiffAndRevertsToTheFile) {
  const auto operator_port = config.modbus_port;
  const auto moved_port = free_port();
  auto moved = config;
  moved.modbus_port = moved_port;
  const auto good = file_with("moved.yaml", moved.yaml());
  auto broken = moved;
  broken.modbus_port = free_port();
  broken.extra += "no_such_section: 1\n";
  const auto broken_yaml = broken.yaml();
  const auto error_line = std::count(broken_yaml.begin(), broken_yaml.begin() + static_cast<long>(broken_yaml.find("no_such_section")), '\n') + 1;
  const auto bad = file_with("broken.yaml", broken_yaml);

  const auto applied = page_config("fleet:fleet-pass", "--apply-file " + good + " --apply-file " + bad);
  ASSERT_TRUE(applied.contains("steps")) << applied;
  const auto& first = applied["first"];
  EXPECT_EQ(first["hidden"], false) << first;
  EXPECT_EQ(first["source"], "file") << first;
  EXPECT_EQ(first["may_change"], true) << first;
  EXPECT_EQ(first["form"]["shown"], true) << first;
  EXPECT_NE(config_line(first, "in-force")["text"].get<std::string>().find(daemon->config_path().string()), std::string::npos) << first;
  ASSERT_EQ(applied["steps"].size(), 2u) << applied;

  // (a) The file applies: the box waits with its buttons off, then says so in green and
  // shows the config from http by fleet, kept as 1, and the changed line.
  const auto& put = applied["steps"][0];
  ASSERT_FALSE(put["states"].empty()) << put;
  EXPECT_EQ(put["states"][0]["state"], "waiting") << put;
  EXPECT_EQ(put["states"][0]["disabled"], true) << put;
  EXPECT_NE(put["states"][0]["text"].get<std::string>().find("waiting for the answer"), std::string::npos) << put;
  EXPECT_EQ(put["answer"]["result"], "applied") << put;
  EXPECT_EQ(put["answer"]["colour"], page_good_colour) << put;
  const auto& after_put = put["config"];
  EXPECT_EQ(after_put["source"], "http") << after_put;
  EXPECT_EQ(after_put["form"]["disabled"], false) << after_put;
  EXPECT_NE(config_line(after_put, "in-force")["text"].get<std::string>().find("remote config 1 by fleet"), std::string::npos) << after_put;
  EXPECT_EQ(config_line(after_put, "in-force")["title"].get<std::string>().size(), 64u) << "the whole sha256 in the title: " << after_put;
  EXPECT_EQ(config_line(after_put, "last")["result"], "applied") << after_put;
  ASSERT_EQ(after_put["history"].size(), 1u) << after_put;
  EXPECT_EQ(after_put["history"][0]["number"], 1) << after_put;
  EXPECT_EQ(after_put["history"][0]["in_force"], true) << after_put;
  EXPECT_TRUE(diff_has(after_put, "-", port_line(operator_port))) << after_put["diff"];
  EXPECT_TRUE(diff_has(after_put, "+", port_line(moved_port))) << after_put["diff"];
  EXPECT_NE(after_put["diff"]["text"].get<std::string>().find("the operator's file → the config in force"), std::string::npos)
      << after_put["diff"];

  // (b) A file with errors: refused, in red, each error at its line and column; nothing changed.
  const auto& refused = applied["steps"][1];
  EXPECT_EQ(refused["answer"]["result"], "refused") << refused;
  EXPECT_EQ(refused["answer"]["colour"], page_bad_colour) << refused;
  ASSERT_FALSE(refused["answer"]["errors"].empty()) << refused;
  EXPECT_TRUE(refused["answer"]["errors"][0].get<std::string>().starts_with(std::to_string(error_line) + ":")) << refused;
  EXPECT_EQ(refused["config"]["source"], "http") << refused;
  EXPECT_EQ(refused["config"]["history"].size(), 1u) << refused;
  EXPECT_EQ(config_line(refused["config"], "last")["result"], "refused") << refused;
  EXPECT_TRUE(serves_on(moved_port));
  EXPECT_FALSE(serves_on(operator_port));

  // (c) Back to the operator's file through the page: its port serves again.
  const auto reverted = page_config("fleet:fleet-pass", "--revert");
  ASSERT_EQ(reverted["steps"].size(), 1u) << reverted;
  const auto& revert = reverted["steps"][0];
  EXPECT_EQ(revert["answer"]["result"], "applied") << revert;
  const auto& after_revert = revert["config"];
  EXPECT_EQ(after_revert["source"], "file") << after_revert;
  ASSERT_EQ(after_revert["history"].size(), 1u) << after_revert;
  EXPECT_EQ(after_revert["history"][0]["in_force"], false) << after_revert;
  EXPECT_TRUE(diff_has(after_revert, "-", port_line(moved_port))) << after_revert["diff"];
  EXPECT_TRUE(diff_has(after_revert, "+", port_line(operator_port))) << after_revert["diff"];
  EXPECT_TRUE(serves_on(operator_port));
  EXPECT_TRUE(daemon->wait_for_log("remote config: http by fleet: applied, the operator's file")) << daemon->log();
}

TEST_F(PageConfig, AnUnlistedUserSeesTheConfigInForceAndItsHistoryButNeitherTheFormNorTheText) {
  auto moved = config;
  moved.modbus_port = free_port();
  const auto put = run("curl -sS --max-time 60 --cacert " + pem("ca.pem") + " -u fleet:fleet-pass -X PUT --data-binary @" +
                       file_with("moved.yaml", moved.yaml()) + " https://127.0.0.1:" + std::to_string(http_port) + "/api/config");
  ASSERT_NE(put.output.find("\"applied\""), std::string::npos) << put.output << daemon->log();

  const auto shown = page_config("technician:tech-pass");
  const auto& box = shown["config"];
  EXPECT_EQ(box["hidden"], false) << box;
  EXPECT_EQ(box["source"], "http") << box;
  EXPECT_EQ(box["may_change"], false) << box;
  EXPECT_NE(config_line(box, "in-force")["text"].get<std::string>().find("by fleet"), std::string::npos) << box;
  EXPECT_EQ(box["history"].size(), 1u) << box;
  EXPECT_EQ(box["form"]["shown"], false) << box;
  EXPECT_EQ(box["diff"]["shown"], false) << box;
  EXPECT_TRUE(box["diff"]["lines"].empty()) << box;
  EXPECT_EQ(box["text"].get<std::string>().find("tcp: {"), std::string::npos) << "no line of the text on the page: " << box;
}

}  // namespace
}  // namespace unima::test
