// tls::MemorySession: the TLS port's session over memory (SPEC §11) against OpenSSL's own
// client over memory (tests/support/peers/memory_tls_client) — a handshake, records split
// anywhere, a request that comes with the client's Finished, KeyUpdates both ways, padded
// records, answers longer than a record, close_notify, forged records and bytes that are
// not TLS, the server's own close_notify, no tickets and no renegotiation. Every record is
// OpenSSL's (SPEC §11), for TLS 1.3 and 1.2. A self-signed ECDSA P-256 certificate made here.

#include <gtest/gtest.h>

#include <openssl/evp.h>
#include <openssl/x509.h>

#include <string>
#include <vector>

#include "tests/support/peers/memory_tls_client.hpp"
#include "tls/memory_session.hpp"
#include "tls/server_credentials.hpp"

namespace unima::tls {
namespace {

using Status = MemorySession::Status;

class MemorySessionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    key_ = EVP_EC_gen("P-256");
    cert_ = X509_new();
    ASN1_INTEGER_set(X509_get_serialNumber(cert_), 1);
    X509_gmtime_adj(X509_getm_notBefore(cert_), 0);
    X509_gmtime_adj(X509_getm_notAfter(cert_), 3600);
    X509_set_pubkey(cert_, key_);
    X509_NAME_add_entry_by_txt(X509_get_subject_name(cert_), "CN", MBSTRING_ASC,
                               reinterpret_cast<const unsigned char*>("server"), -1, -1, 0);
    X509_set_issuer_name(cert_, X509_get_subject_name(cert_));
    X509_sign(cert_, key_, EVP_sha256());
    server_context_ = SSL_CTX_new(TLS_server_method());
    SSL_CTX_use_certificate(server_context_, cert_);
    SSL_CTX_use_PrivateKey(server_context_, key_);
    apply_server_policy(server_context_);  // as the port's contexts: no tickets, no renegotiation
    client_context_ = SSL_CTX_new(TLS_client_method());
    tls_client_ = std::make_unique<test_support::MemoryTlsClient>(client_context_);
    client_ = tls_client_->ssl();
    server_ = std::make_unique<MemorySession>(server_context_);
  }
  void TearDown() override {
    server_.reset();
    tls_client_.reset();
    SSL_CTX_free(client_context_);
    SSL_CTX_free(server_context_);
    X509_free(cert_);
    EVP_PKEY_free(key_);
  }

  std::vector<std::uint8_t> from_client() { return tls_client_->take_output(); }
  void to_client() {
    std::vector<std::uint8_t> bytes;
    server_->take_output(bytes);
    tls_client_->give_input(bytes);
  }
  // Until the client's handshake is done; its Finished stays in its output.
  void handshake_but_the_last_flight() {
    ASSERT_NE(SSL_do_handshake(client_), 1);
    server_->feed(from_client());
    ASSERT_EQ(server_->handshake(), Status::want_input);
    to_client();
    ASSERT_EQ(SSL_do_handshake(client_), 1);
  }
  void handshake() {
    handshake_but_the_last_flight();
    server_->feed(from_client());
    ASSERT_EQ(server_->handshake(), Status::done);
    to_client();
  }
  void send_from_client(const std::string& text) {
    ASSERT_EQ(SSL_write(client_, text.data(), static_cast<int>(text.size())), static_cast<int>(text.size()));
    server_->feed(from_client());
  }
  void answer(const std::string& text) {
    ASSERT_TRUE(server_->write(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size())));
    to_client();
  }
  std::string read_at_client() {
    std::string text;
    char buffer[4096];
    int n = 0;
    while ((n = SSL_read(client_, buffer, sizeof buffer)) > 0) text.append(buffer, static_cast<std::size_t>(n));
    return text;
  }
  std::string read_all() {
    std::string text;
    std::uint8_t buffer[64];
    std::size_t n = 0;
    while (server_->read(buffer, n) == Status::done) text.append(reinterpret_cast<char*>(buffer), n);
    return text;
  }

  EVP_PKEY* key_ = nullptr;
  X509* cert_ = nullptr;
  SSL_CTX* server_context_ = nullptr;
  SSL_CTX* client_context_ = nullptr;
  std::unique_ptr<test_support::MemoryTlsClient> tls_client_;
  SSL* client_ = nullptr;  // tls_client_'s session
  std::unique_ptr<MemorySession> server_;
};

TEST_F(MemorySessionTest, ARequestThatComesWithTheFinishedIsReadOnceTheHandshakeIsDone) {
  handshake_but_the_last_flight();
  ASSERT_EQ(SSL_write(client_, "request", 7), 7);
  server_->feed(from_client());  // Finished and the request in one piece
  EXPECT_FALSE(server_->handshaken());
  EXPECT_EQ(server_->handshake(), Status::done);
  EXPECT_TRUE(server_->handshaken());
  EXPECT_EQ(read_all(), "request");

  ASSERT_TRUE(server_->write(std::span(reinterpret_cast<const std::uint8_t*>("answer"), 6)));
  EXPECT_TRUE(server_->has_output());
  to_client();
  EXPECT_FALSE(server_->has_output());
  char answer[16];
  ASSERT_EQ(SSL_read(client_, answer, sizeof answer), 6);
  EXPECT_EQ(std::string(answer, 6), "answer");
}

TEST_F(MemorySessionTest, ARecordFedByteByByteIsReadWhenItIsWhole) {
  handshake_but_the_last_flight();
  server_->feed(from_client());
  ASSERT_EQ(server_->handshake(), Status::done);
  ASSERT_EQ(SSL_write(client_, "0123456789", 10), 10);
  const auto record = from_client();
  std::size_t n = 0;
  std::uint8_t buffer[32];
  for (std::size_t i = 0; i + 1 < record.size(); ++i) {
    server_->feed(std::span(&record[i], 1));
    ASSERT_EQ(server_->read(buffer, n), Status::want_input) << "after byte " << i;
  }
  server_->feed(std::span(&record.back(), 1));
  ASSERT_EQ(server_->read(buffer, n), Status::done);
  EXPECT_EQ(std::string(reinterpret_cast<char*>(buffer), n), "0123456789");
}

TEST_F(MemorySessionTest, CloseNotifyIsClosedAndGarbageIsAFailureWithAReason) {
  handshake_but_the_last_flight();
  server_->feed(from_client());
  ASSERT_EQ(server_->handshake(), Status::done);
  SSL_shutdown(client_);
  server_->feed(from_client());
  std::uint8_t buffer[8];
  std::size_t n = 0;
  EXPECT_EQ(server_->read(buffer, n), Status::closed);

  MemorySession other(server_context_);
  const std::string not_tls = "GET / HTTP/1.1\r\n\r\n";
  other.feed(std::span(reinterpret_cast<const std::uint8_t*>(not_tls.data()), not_tls.size()));
  EXPECT_EQ(other.handshake(), Status::failed);
  EXPECT_FALSE(other.error().empty());
}

// RFC 8446 §4.6.3: a client may renew its key, and ask the server to renew its own.
TEST_F(MemorySessionTest, AClientsKeyUpdateIsFollowedAndAnsweredWhenItAsks) {
  handshake();
  ASSERT_EQ(SSL_key_update(client_, SSL_KEY_UPDATE_REQUESTED), 1);
  send_from_client("after the update");
  EXPECT_EQ(read_all(), "after the update");
  answer("under the server's next key");
  EXPECT_EQ(read_at_client(), "under the server's next key");
  ASSERT_EQ(SSL_key_update(client_, SSL_KEY_UPDATE_NOT_REQUESTED), 1);
  send_from_client("second");
  EXPECT_EQ(read_all(), "second");
  answer("and again");
  EXPECT_EQ(read_at_client(), "and again");
}

TEST_F(MemorySessionTest, PaddedRecordsAreReadWithoutTheirPadding) {
  handshake();
  ASSERT_EQ(SSL_set_block_padding(client_, 512), 1);
  send_from_client("request");
  EXPECT_EQ(read_all(), "request");
}

TEST_F(MemorySessionTest, AnAnswerLongerThanARecordArrivesWhole) {
  handshake();
  std::string long_answer(40000, '\0');
  for (std::size_t i = 0; i < long_answer.size(); ++i) long_answer[i] = static_cast<char>('a' + i % 26);
  answer(long_answer);
  EXPECT_EQ(read_at_client(), long_answer);
}

TEST_F(MemorySessionTest, AForgedRecordEndsTheSessionWithAReasonAndTheClientIsTold) {
  handshake();
  ASSERT_EQ(SSL_write(client_, "write W", 7), 7);
  auto record = from_client();
  record.back() ^= 0x01;  // a bit of the tag
  server_->feed(record);
  std::uint8_t buffer[16];
  std::size_t n = 0;
  EXPECT_EQ(server_->read(buffer, n), Status::failed);
  EXPECT_EQ(n, 0U);
  EXPECT_FALSE(server_->error().empty());
  to_client();
  char answer[16];
  EXPECT_LE(SSL_read(client_, answer, sizeof answer), 0);
  EXPECT_EQ(SSL_get_error(client_, -1), SSL_ERROR_SSL);  // the server's alert, not "want more"
}

// SPEC §11: the port's policy issues no session ticket (a TLS 1.3 client reads none after
// the handshake and an answer).
TEST_F(MemorySessionTest, NoSessionTicketIsIssued) {
  handshake();
  send_from_client("request");
  EXPECT_EQ(read_all(), "request");
  answer("answer");
  EXPECT_EQ(read_at_client(), "answer");
  EXPECT_EQ(SSL_SESSION_has_ticket(SSL_get_session(client_)), 0);
}

// RFC 8446 §6.1: the server closes cleanly with its own close_notify, which the client
// reads as the end of the stream; after the client's close_notify the server's answers it.
TEST_F(MemorySessionTest, TheServersCloseNotifyEndsTheClientsStreamCleanly) {
  handshake();
  send_from_client("request");
  EXPECT_EQ(read_all(), "request");
  ASSERT_TRUE(server_->close_notify());
  EXPECT_FALSE(server_->close_notify()) << "said once";
  to_client();
  char buffer[8];
  EXPECT_EQ(SSL_read(client_, buffer, sizeof buffer), 0);
  EXPECT_EQ(SSL_get_error(client_, 0), SSL_ERROR_ZERO_RETURN);
}

TEST_F(MemorySessionTest, AfterTheClientsCloseNotifyTheServerAnswersWithItsOwn) {
  handshake();
  ASSERT_EQ(SSL_shutdown(client_), 0);  // sent, the server's not yet received
  server_->feed(from_client());
  std::uint8_t buffer[8];
  std::size_t n = 0;
  ASSERT_EQ(server_->read(buffer, n), Status::closed);
  ASSERT_TRUE(server_->close_notify());
  to_client();
  EXPECT_EQ(SSL_shutdown(client_), 1);  // both sides closed
}

TEST_F(MemorySessionTest, NoCloseNotifyBeforeTheHandshakeOrAfterAFailure) {
  EXPECT_FALSE(server_->close_notify()) << "nothing to close before a handshake";
  handshake();
  ASSERT_EQ(SSL_write(client_, "write W", 7), 7);
  auto record = from_client();
  record.back() ^= 0x01;
  server_->feed(record);
  std::uint8_t buffer[16];
  std::size_t n = 0;
  ASSERT_EQ(server_->read(buffer, n), Status::failed);
  std::vector<std::uint8_t> alert;
  server_->take_output(alert);
  EXPECT_FALSE(server_->close_notify()) << "OpenSSL says nothing more after a fatal alert";
  EXPECT_FALSE(server_->has_output());
}

// A finite-field key share (up to ffdhe8192, a tenth of a second of the server's CPU a
// step) is refused in the handshake: the port takes X25519, P-256 and P-384 only.
TEST_F(MemorySessionTest, AFiniteFieldKeyExchangeIsRefusedAndP384IsTaken) {
  ASSERT_EQ(SSL_set1_groups_list(client_, "ffdhe3072:ffdhe8192"), 1);
  ASSERT_NE(SSL_do_handshake(client_), 1);
  server_->feed(from_client());
  EXPECT_EQ(server_->handshake(), Status::failed);

  test_support::MemoryTlsClient p384_client(client_context_);
  ASSERT_EQ(SSL_set1_groups_list(p384_client.ssl(), "P-384"), 1);
  MemorySession server(server_context_);
  ASSERT_NE(SSL_do_handshake(p384_client.ssl()), 1);
  server.feed(p384_client.take_output());
  EXPECT_EQ(server.handshake(), Status::want_input) << server.error();
}

TEST(MemorySessionTls12, ATls12SessionReadsAndWritesWithNoTicketAndNoRenegotiation) {
  EVP_PKEY* key = EVP_EC_gen("P-256");
  X509* cert = X509_new();
  X509_gmtime_adj(X509_getm_notBefore(cert), 0);
  X509_gmtime_adj(X509_getm_notAfter(cert), 3600);
  X509_set_pubkey(cert, key);
  X509_sign(cert, key, EVP_sha256());
  SSL_CTX* server_context = SSL_CTX_new(TLS_server_method());
  SSL_CTX_use_certificate(server_context, cert);
  SSL_CTX_use_PrivateKey(server_context, key);
  apply_server_policy(server_context);
  SSL_CTX* client_context = SSL_CTX_new(TLS_client_method());
  SSL_CTX_set_max_proto_version(client_context, TLS1_2_VERSION);
  {
    test_support::MemoryTlsClient tls_client(client_context);
    SSL* client = tls_client.ssl();
    MemorySession server(server_context);
    const auto pass = [&] {
      auto bytes = tls_client.take_output();
      server.feed(bytes);
      const auto status = server.handshake();
      bytes.clear();
      server.take_output(bytes);
      tls_client.give_input(bytes);
      return status;
    };
    for (int round = 0; round < 4 && !server.handshaken(); ++round) {
      SSL_do_handshake(client);
      pass();
    }
    ASSERT_TRUE(server.handshaken());
    ASSERT_EQ(SSL_do_handshake(client), 1);
    EXPECT_EQ(SSL_version(server.native_handle()), TLS1_2_VERSION);
    ASSERT_EQ(SSL_write(client, "twelve", 6), 6);
    server.feed(tls_client.take_output());
    std::uint8_t buffer[16];
    std::size_t n = 0;
    ASSERT_EQ(server.read(buffer, n), Status::done);
    EXPECT_EQ(std::string(reinterpret_cast<char*>(buffer), n), "twelve");
    ASSERT_TRUE(server.write(std::span(reinterpret_cast<const std::uint8_t*>("answer"), 6)));
    std::vector<std::uint8_t> bytes;
    server.take_output(bytes);
    tls_client.give_input(bytes);
    char answer[16];
    ASSERT_EQ(SSL_read(client, answer, sizeof answer), 6);
    EXPECT_EQ(std::string(answer, 6), "answer");
    EXPECT_EQ(SSL_SESSION_has_ticket(SSL_get_session(client)), 0);

    // SPEC §11: a renegotiation the client asks for is refused, and no second handshake runs.
    ASSERT_EQ(SSL_renegotiate(client), 1);
    EXPECT_NE(SSL_do_handshake(client), 1);
    server.feed(tls_client.take_output());
    EXPECT_NE(server.read(buffer, n), Status::done);
    bytes.clear();
    server.take_output(bytes);
    EXPECT_FALSE(bytes.empty()) << "the server's no_renegotiation alert";
    tls_client.give_input(bytes);
    const int renegotiated = SSL_do_handshake(client);
    EXPECT_EQ(SSL_get_error(client, renegotiated), SSL_ERROR_SSL) << "refused, not waiting for the server's flight";
  }
  SSL_CTX_free(client_context);
  SSL_CTX_free(server_context);
  X509_free(cert);
  EVP_PKEY_free(key);
}

}  // namespace
}  // namespace unima::tls
