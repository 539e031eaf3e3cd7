// A change from afar builds its TLS contexts on the coordinator's worker
// (io::prepare_server_tls_contexts); the stage, on the event loop, takes them instead of
// reading the certificate and key again — unless a file changed since, when it reads them.

#include <sys/stat.h>

#include <filesystem>

#include <gtest/gtest.h>

#include "io/tls_context.hpp"
#include "tests/integration/certificate_fixture.hpp"

namespace unima::test {
namespace {

class TlsContextCache : public CertificateTest {
 protected:
  config::Config with_modbus_tls() const {
    config::Config next;
    next.modbus.tls.emplace();
    next.modbus.tls->certificate = pem("server.pem");
    next.modbus.tls->key = pem("server.key");
    next.modbus.tls->ca = pem("ca.pem");
    return next;
  }
};

TEST_F(TlsContextCache, TheStageTakesTheContextPreparedForTheSameUnchangedFiles) {
  const auto next = with_modbus_tls();
  const auto files = io::modbus_tls_files(*next.modbus.tls);
  io::prepare_server_tls_contexts(next);
  const auto before = io::prepared_tls_contexts_taken();
  EXPECT_NE(io::make_server_tls_context(files), nullptr);
  EXPECT_EQ(io::prepared_tls_contexts_taken(), before + 1) << "taken ready";
  EXPECT_NE(io::make_server_tls_context(files), nullptr);
  EXPECT_EQ(io::prepared_tls_contexts_taken(), before + 1) << "taken once: the next one is read again";
}

TEST_F(TlsContextCache, ACertificateChangedSinceIsReadAgain) {
  const auto next = with_modbus_tls();
  const auto files = io::modbus_tls_files(*next.modbus.tls);
  io::prepare_server_tls_contexts(next);
  const auto before = io::prepared_tls_contexts_taken();
  // Renewed in place: the same bytes, a later time.
  const auto certificate = std::filesystem::path(files.certificate);
  std::filesystem::last_write_time(certificate, std::filesystem::last_write_time(certificate) + std::chrono::seconds(5));
  EXPECT_NE(io::make_server_tls_context(files), nullptr);
  EXPECT_EQ(io::prepared_tls_contexts_taken(), before) << "the prepared one was stale";
  // Gone since: the stage says so, as it did before any context was prepared.
  io::prepare_server_tls_contexts(next);
  std::filesystem::remove(files.key);
  EXPECT_THROW(io::make_server_tls_context(files), std::runtime_error);
  EXPECT_EQ(io::prepared_tls_contexts_taken(), before);
}

}  // namespace
}  // namespace unima::test
