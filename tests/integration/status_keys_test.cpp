// The status document's contract (issue 38): every key of `unima-bridge status --json`
// (array elements' keys merged) and every /metrics family (name, TYPE, HELP), with every
// part of the daemon on, compared with the golden lists in tests/golden/. The document's
// four readers (/metrics, the CLI panel, the page, the HTTP panels) read these keys: a key
// renamed, lost or added by mistake fails here. A deliberate change rewrites the lists:
// UNIMA_UPDATE_GOLDEN=1 ctest -R StatusKeys, then review the diff.

#include <cstdlib>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "tests/integration/certificate_fixture.hpp"
#include "tests/integration/cli_under_test.hpp"
#include "tests/integration/gateway_fixture.hpp"
#include "tests/support/peers/http_exchange.hpp"
#include "tests/support/peers/mqtt_broker.hpp"

namespace unima::test {
namespace {

const std::filesystem::path golden_dir = std::filesystem::path(UNIMA_SOURCE_DIR) / "tests" / "golden";

// Every path of `value`: "a", "a.b", "a[]", "a[].c" (the keys of all of an array's elements).
void collect_paths(const nlohmann::json& value, const std::string& path, std::set<std::string>& out) {
  if (value.is_object()) {
    for (const auto& [key, item] : value.items()) {
      const auto inner = path.empty() ? key : path + "." + key;
      out.insert(inner);
      collect_paths(item, inner, out);
    }
  } else if (value.is_array()) {
    out.insert(path + "[]");
    for (const auto& item : value) collect_paths(item, path + "[]", out);
  }
}

std::string key_set(const nlohmann::json& status) {
  std::set<std::string> paths;
  collect_paths(status, "", paths);
  std::string text;
  for (const auto& path : paths) text += path + "\n";
  return text;
}

// One line per family, in the order of the exposition: "NAME TYPE HELP".
std::string families(const std::string& exposition) {
  std::istringstream lines(exposition);
  std::string out, help_name, help;
  for (std::string line; std::getline(lines, line);) {
    if (line.starts_with("# HELP ")) {
      const auto rest = line.substr(7);
      help_name = rest.substr(0, rest.find(' '));
      help = rest.substr(rest.find(' ') + 1);
    } else if (line.starts_with("# TYPE ")) {
      const auto rest = line.substr(7);
      const auto name = rest.substr(0, rest.find(' '));
      out += name + " " + rest.substr(rest.find(' ') + 1) + " " + (name == help_name ? help : "(no HELP)") + "\n";
    }
  }
  return out;
}

// Compares `actual` with the golden file `name`, or writes it when UNIMA_UPDATE_GOLDEN is set.
void expect_golden(const std::string& name, const std::string& actual) {
  const auto file = golden_dir / name;
  if (const char* update = std::getenv("UNIMA_UPDATE_GOLDEN"); update && *update) {
    test_support::write_file(file, actual);
    return;
  }
  EXPECT_EQ(test_support::read_file(file), actual) << "tests/golden/" << name << " (UNIMA_UPDATE_GOLDEN=1 rewrites it)";
}

// With UNIMA_UPDATE_GOLDEN, the document itself too: tests/unit/metrics_test.cpp renders it
// and compares the whole exposition, every sample's value included.
void keep_document(const std::string& name, const nlohmann::json& status) {
  if (const char* update = std::getenv("UNIMA_UPDATE_GOLDEN"); update && *update)
    test_support::write_file(golden_dir / name, status.dump(2) + "\n");
}

nlohmann::json status_of(const std::string& socket) {
  const auto r = run(bridge_cli() + " status --json --socket " + socket);
  return r.status == 0 ? nlohmann::json::parse(r.output, nullptr, false) : nlohmann::json();
}

// Slave mode with everything a slave has: the Modbus TCP and Modbus/TCP Security ports,
// a feed client, devices and modules, the monitor with an indicator, the state file, MQTT
// with its buffer, Sparkplug with a primary host, HTTPS with users.
class StatusKeys : public CertificateTest {
 protected:
  void SetUp() override {
    CertificateTest::SetUp();
    broker = std::make_unique<test_support::Broker>(dir.path());
    ASSERT_TRUE(broker->start());
  }
  void start_everything() {
    const auto users = dir.path() / "http-users";
    test_support::write_file(users, "technician:$2b$04$rYgRiVE3kuiWbV7187bbNeSC1qtsbryLJKemMQUpFpIZgisrpvzAO\n");
    tls_port = free_port();
    http_port = free_port();
    const auto broker_url = "'mqtt://127.0.0.1:" + std::to_string(broker->port()) + "'";
    config.modbus_extra = tls_section(tls_port, "{ operator: { write: [W] } }");
    config.monitor_section = "monitor:\n  file: " + (dir.path() / "monitor.log").string() +
                             "\n  indicators: [ { address: 1, register: 0x0100 } ]\n";
    config.extra += "state: { file: " + (dir.path() / "state").string() + " }\n";
    config.extra += "mqtt: { broker: " + broker_url + ", client_id: site-17, topic: fleet/site-17, publish: { period: 60s }, " +
                    "buffer: { file: " + (dir.path() / "mqtt-buffer").string() + " } }\n";
    config.extra += "sparkplug: { broker: " + broker_url + ", group_id: plant-7, edge_node_id: bridge-17, primary_host: scada-1 }\n";
    config.extra += "http: { listen: 127.0.0.1, port: " + std::to_string(http_port) + ", users: " + users.string() +
                    ", tls: { certificate: " + pem("server.pem") + ", key: " + pem("server.key") + " } }\n";
    start();
    ASSERT_TRUE(wait_for_port(http_port)) << daemon->log();
    ASSERT_TRUE(wait_for_port(tls_port)) << daemon->log();
  }

  std::unique_ptr<test_support::Broker> broker;
  std::uint16_t tls_port = 0;
  std::uint16_t http_port = 0;
};

// The metrics come over HTTPS (https_get.py prints the body with its newlines as "\\n").
TEST_F(StatusKeys, TheSlavesDocumentAndMetricsHaveTheGoldenKeys) {
  start_everything();
  auto feed = feed_client();
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.read_holding(0x0100, 1));
  // Every part has said what it has: MQTT and Sparkplug connected (their keys stand either
  // way; waiting makes the document the same each run), the feed client counted.
  nlohmann::json status;
  ASSERT_TRUE(eventually([&] {
    status = status_of(config.status_socket);
    return status.is_object() && status["mqtt"]["connected"] == true && status["sparkplug"]["connected"] == true &&
           status["unimabus"]["clients"] == 1;
  })) << status.dump(1) << daemon->log();
  expect_golden("status_keys_slave.txt", key_set(status));
  keep_document("status_slave.json", status);

  const auto fetched = run(tls_dir + "/https_get.py " + std::to_string(http_port) + " /metrics " + pem("ca.pem") +
                           " technician:right");
  ASSERT_EQ(fetched.status, 0) << fetched.output;
  const auto at = fetched.output.find("body: ");
  ASSERT_NE(at, std::string::npos) << fetched.output;
  std::string body;
  const auto escaped = fetched.output.substr(at + 6);
  for (std::size_t i = 0; i < escaped.size(); ++i) {
    if (escaped.compare(i, 2, "\\n") == 0) {
      body += '\n';
      ++i;
    } else {
      body += escaped[i];
    }
  }
  expect_golden("metrics_families_slave.txt", families(body));
}

// Master mode: the master's devices, its port, the gateway and a unit a client asked for.
class StatusKeysOfTheGateway : public GatewayTest {};

TEST_F(StatusKeysOfTheGateway, TheMastersDocumentAndMetricsHaveTheGoldenKeys) {
  const auto http_port = free_port();
  config.extra += "http: { listen: 127.0.0.1, port: " + std::to_string(http_port) + " }\n";
  start_with("{ units: [5-7], priority: [127.0.0.1], timeout: 200ms, wait: 5s, cache: 100ms }");
  ASSERT_TRUE(wait_for_port(http_port)) << diagnostics();
  auto socket = Socket::tcp(config.modbus_port);
  ASSERT_TRUE(ask(socket, 1, plc, Bytes{0x03, 0x00, 0x00, 0x00, 0x01})) << diagnostics();
  nlohmann::json status;
  ASSERT_TRUE(eventually([&] {
    status = status_of(config.status_socket);
    if (!status.is_object() || !status.contains("master") || status["gateway"]["units"].empty()) return false;
    for (const auto& port : status["ports"])
      if (port["port"] == "master") return true;
    return false;
  })) << status.dump(1) << diagnostics();
  expect_golden("status_keys_master.txt", key_set(status));
  keep_document("status_master.json", status);

  const auto metrics = test_support::http_get(http_port, "/metrics");
  ASSERT_EQ(metrics.status, 200);
  expect_golden("metrics_families_master.txt", families(metrics.body));
}

}  // namespace
}  // namespace unima::test
