// tls::MemorySession: the TLS port's session over memory (SPEC §11) against OpenSSL's own
// client over memory — a handshake, records split anywhere, a request that comes with the
// client's Finished, close_notify, and bytes that are not TLS. A self-signed ECDSA P-256
// certificate made here.

#include <gtest/gtest.h>

#include <openssl/evp.h>
#include <openssl/x509.h>

#include <string>
#include <vector>

#include "tls/memory_session.hpp"

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
    client_context_ = SSL_CTX_new(TLS_client_method());
    client_ = SSL_new(client_context_);
    client_in_ = BIO_new(BIO_s_mem());
    client_out_ = BIO_new(BIO_s_mem());
    BIO_set_mem_eof_return(client_in_, -1);
    SSL_set_bio(client_, client_in_, client_out_);
    SSL_set_connect_state(client_);
    server_ = std::make_unique<MemorySession>(server_context_);
  }
  void TearDown() override {
    server_.reset();
    SSL_free(client_);
    SSL_CTX_free(client_context_);
    SSL_CTX_free(server_context_);
    X509_free(cert_);
    EVP_PKEY_free(key_);
  }

  std::vector<std::uint8_t> from_client() {
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(BIO_ctrl_pending(client_out_)));
    BIO_read(client_out_, bytes.data(), static_cast<int>(bytes.size()));
    return bytes;
  }
  void to_client() {
    std::vector<std::uint8_t> bytes;
    server_->take_output(bytes);
    BIO_write(client_in_, bytes.data(), static_cast<int>(bytes.size()));
  }
  // Until the client's handshake is done; its Finished stays in its output.
  void handshake_but_the_last_flight() {
    ASSERT_NE(SSL_do_handshake(client_), 1);
    server_->feed(from_client());
    ASSERT_EQ(server_->handshake(), Status::want_input);
    to_client();
    ASSERT_EQ(SSL_do_handshake(client_), 1);
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
  SSL* client_ = nullptr;
  BIO* client_in_ = nullptr;
  BIO* client_out_ = nullptr;
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

}  // namespace
}  // namespace unima::tls
