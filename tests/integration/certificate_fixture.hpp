#pragma once
// A running bridge's test with the certificates of tests/integration/tls/make_certificates.sh
// (a CA, the server's for 127.0.0.1 and its renewal, clients with and without a role, a
// stranger of another CA), made by the openssl command line in the test's directory.

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

  std::filesystem::path certs;
};

}  // namespace unima::test
