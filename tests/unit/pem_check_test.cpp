// What is wrong with a PEM file the config names, in a technician's words (tls/pem_check),
// and check_on_host saying it at the key's line for every PEM key of the config (issue 30, 6).

#include <gtest/gtest.h>
#include <openssl/pem.h>
#include <openssl/x509.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <ctime>
#include <string>

#include "config/config.hpp"
#include "tests/support/error_message.hpp"
#include "tests/support/temp_files.hpp"
#include "tls/pem_check.hpp"

namespace unima::tls {
namespace {

using test_support::TempDir;

constexpr std::time_t issued = 1'800'000'000;  // the certificates' notBefore; valid 30 days
constexpr std::time_t day = 86'400;

// A P-256 key and its self-signed certificate, written as PEM into `dir`/`name`.key and .pem.
void make_pair(const TempDir& dir, const std::string& name) {
  EVP_PKEY* key = EVP_EC_gen("P-256");
  X509* certificate = X509_new();
  ASN1_INTEGER_set(X509_get_serialNumber(certificate), 1);
  std::time_t from = issued;
  X509_time_adj_ex(X509_getm_notBefore(certificate), 0, 0, &from);
  X509_time_adj_ex(X509_getm_notAfter(certificate), 30, 0, &from);
  X509_set_pubkey(certificate, key);
  X509_NAME_add_entry_by_txt(X509_get_subject_name(certificate), "CN", MBSTRING_ASC,
                             reinterpret_cast<const unsigned char*>(name.c_str()), -1, -1, 0);
  X509_set_issuer_name(certificate, X509_get_subject_name(certificate));
  X509_sign(certificate, key, EVP_sha256());
  std::FILE* key_file = std::fopen((dir.path() / (name + ".key")).c_str(), "w");
  PEM_write_PrivateKey(key_file, key, nullptr, nullptr, 0, nullptr, nullptr);
  std::fclose(key_file);
  std::FILE* certificate_file = std::fopen((dir.path() / (name + ".pem")).c_str(), "w");
  PEM_write_X509(certificate_file, certificate);
  std::fclose(certificate_file);
  X509_free(certificate);
  EVP_PKEY_free(key);
}

class PemCheck : public ::testing::Test {
 protected:
  void SetUp() override {
    make_pair(dir, "server");
    make_pair(dir, "other");
    test_support::write_file(dir.path() / "garbage.pem", "not a PEM file\n");
  }
  std::string file(const std::string& name) const { return (dir.path() / name).string(); }
  TempDir dir;
};

TEST_F(PemCheck, SaysWhatIsWrongWithAFileAndWhatToDo) {
  EXPECT_FALSE(pem_file_problem(file("server.pem"), PemContent::certificate));
  EXPECT_FALSE(pem_file_problem(file("server.key"), PemContent::private_key));
  EXPECT_FALSE(pem_file_problem(file("server.pem"), PemContent::ca_certificates));
  EXPECT_EQ(pem_file_problem(file("gone.key"), PemContent::private_key), "no such file: correct the path, or put the file there");
  EXPECT_EQ(pem_file_problem(file("server.pem"), PemContent::private_key),
            "a certificate, not a private key: are the certificate and key files swapped?");
  EXPECT_EQ(pem_file_problem(file("server.key"), PemContent::certificate),
            "a private key, not a certificate: are the certificate and key files swapped?");
  EXPECT_TRUE(pem_file_problem(file("garbage.pem"), PemContent::private_key)->starts_with("not a PEM private key"));
  EXPECT_TRUE(pem_file_problem(file("garbage.pem"), PemContent::certificate)->starts_with("not a PEM certificate"));
  EXPECT_EQ(pem_file_problem(dir.path().string(), PemContent::ca_certificates), "a directory, not a PEM file: name the file in it");
  if (::geteuid() != 0) {  // root reads any file
    ::chmod(file("server.key").c_str(), 0);
    EXPECT_TRUE(pem_file_problem(file("server.key"), PemContent::private_key)->starts_with("not readable by user "));
  }
}

TEST_F(PemCheck, AKeyMustBelongToItsCertificate) {
  EXPECT_FALSE(key_mismatch(file("server.pem"), file("server.key"), "modbus.tls.certificate"));
  EXPECT_EQ(key_mismatch(file("server.pem"), file("other.key"), "modbus.tls.certificate"),
            "this key does not belong to the certificate of modbus.tls.certificate (" + file("server.pem") +
                "): give the key the certificate was made for, or the certificate made for this key");
}

TEST_F(PemCheck, ACertificateOutOfItsValidityAtTheTimeGiven) {
  EXPECT_FALSE(certificate_out_of_date(file("server.pem"), issued + day));
  EXPECT_TRUE(certificate_out_of_date(file("server.pem"), issued + 31 * day)->starts_with("the certificate expired on "));
  EXPECT_TRUE(certificate_out_of_date(file("server.pem"), issued - day)->starts_with("the certificate is valid only from "));
}

TEST_F(PemCheck, TheHostCheckNamesTheKeyAtItsLineForEveryPemKeyOfTheConfig) {
  const auto host_error = [&](const std::string& yaml) {
    auto config = config::parse_text(yaml, "bridge.yaml", config::Host{});
    return test_support::error_message<config::ConfigError>([&] { config::check_on_host(config); });
  };
  const auto tls = [&](const std::string& certificate, const std::string& key) {
    return "modbus:\n  tls:\n    certificate: " + file(certificate) + "\n    key: " + file(key) + "\n    ca: " +
           file("server.pem") + "\nstate: { file: none }\n";
  };
  EXPECT_EQ(host_error(tls("server.pem", "gone.key")),
            "bridge.yaml:4:10: modbus.tls.key: " + file("gone.key") + ": no such file: correct the path, or put the file there");
  EXPECT_EQ(host_error(tls("server.pem", "other.key")),
            "bridge.yaml:4:10: modbus.tls.key: " + file("other.key") +
                ": this key does not belong to the certificate of modbus.tls.certificate (" + file("server.pem") +
                "): give the key the certificate was made for, or the certificate made for this key");
  EXPECT_TRUE(host_error(tls("garbage.pem", "server.key"))
                  .starts_with("bridge.yaml:3:18: modbus.tls.certificate: " + file("garbage.pem") + ": not a PEM certificate"));
  EXPECT_NE(host_error("http:\n  tls: { certificate: " + file("server.pem") + ", key: " + file("server.pem") +
                       " }\nstate: { file: none }\n")
                .find(": http.tls.key: " + file("server.pem") + ": a certificate, not a private key"),
            std::string::npos);
  EXPECT_TRUE(host_error("mqtt:\n  broker: mqtts://broker.example\n  ca: " + file("garbage.pem") + "\nstate: { file: none }\n")
                  .starts_with("bridge.yaml:3:7: mqtt.ca: " + file("garbage.pem") + ": not a PEM certificate"));
}

TEST(SerialDeviceCheck, AMissingDeviceIsAWarningSayingWhatTheDaemonDoes) {
  auto slave = config::parse_text("modbus:\n  rtu: { device: /dev/ttyUSB-not-there }\nstate: { file: none }\n",
                                  "bridge.yaml", config::Host{});
  config::check_on_host(slave);
  const auto found = config::warnings(slave);
  ASSERT_EQ(found.size(), 1u) << ::testing::PrintToString(found);
  EXPECT_EQ(found[0], "bridge.yaml:2:18: warning: modbus.rtu.device: /dev/ttyUSB-not-there: no such device; the daemon "
                      "starts without it and tries to open it again every 5 s (an adapter not plugged in yet is fine)");
  auto master = config::parse_text(
      "modbus:\n  mode: master\n  rtu: { device: /dev/ttyUSB-not-there }\nstate: { file: none }\n", "bridge.yaml",
      config::Host{});
  config::check_on_host(master);
  ASSERT_EQ(config::warnings(master).size(), 1u);
  EXPECT_NE(config::warnings(master)[0].find("the master needs its line: the daemon will not start until it can open it"),
            std::string::npos);
}

}  // namespace
}  // namespace unima::tls
