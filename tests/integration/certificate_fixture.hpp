#pragma once
// A running bridge's test with the certificates of tests/integration/tls/make_certificates.sh
// (a CA, the server's for 127.0.0.1 and its renewal, clients with and without a role, a
// stranger of another CA), made by the openssl command line in the test's directory.

#include <cstdint>
#include <filesystem>
#include <string>

#include "tests/integration/bridge_fixture.hpp"

namespace unima::test {

inline const std::string tls_dir = std::string(UNIMA_SOURCE_DIR) + "/tests/integration/tls";

class CertificateTest : public BridgeTest {
 protected:
  void SetUp() override {
    BridgeTest::SetUp();
    certs = dir.path() / "certs";
    const auto made = run(tls_dir + "/make_certificates.sh " + certs.string());
    ASSERT_EQ(made.status, 0) << made.output;
  }
  std::string pem(const std::string& name) const { return (certs / name).string(); }

  /// The `modbus.tls` section of a port on 127.0.0.1:`port` with the server's certificate,
  /// the CA, `roles` (YAML, e.g. "{ operator: { write: [W] } }") and more keys (", k: v").
  std::string tls_section(std::uint16_t port, const std::string& roles, const std::string& extra = "") const {
    return "  tls: { listen: 127.0.0.1, port: " + std::to_string(port) + ", certificate: " + pem("server.pem") +
           ", key: " + pem("server.key") + ", ca: " + pem("ca.pem") + ", roles: " + roles + extra + " }\n";
  }
  /// tests/integration/tls/modbus_tls_client.py as `identity` (its .pem and .key) sending
  /// `requests` (PDUs in hex, space-separated) to 127.0.0.1:`port`.
  test_support::CommandResult tls_client_run(std::uint16_t port, const std::string& identity, const std::string& requests) const {
    return run(tls_dir + "/modbus_tls_client.py " + std::to_string(port) + " " + pem("ca.pem") + " " +
               pem(identity + ".pem") + " " + pem(identity + ".key") + " -- " + requests);
  }

  std::filesystem::path certs;
};

}  // namespace unima::test
