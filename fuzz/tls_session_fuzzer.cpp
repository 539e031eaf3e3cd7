// Fuzz target: what a client sends the Modbus/TCP Security port (SPEC §11), as the port
// hands it to OpenSSL: the ciphertext fed into a server tls::MemorySession, the handshake
// moved on after each piece and, once it completes, the plaintext read and answered —
// what io/modbus/tls_connection does with what its socket read. Every byte of it is
// OpenSSL's to parse (ClientHello and its extensions, records, alerts, the client's
// certificate); the target checks that the session never reports more than it was asked
// for, stops at a failure, and takes its close_notify only when it may.
//
// Input: byte 0 the size of the pieces the socket delivers (0: all at once), the rest the
// client's bytes. The server's context is the port's policy (tls::apply_server_policy)
// with a self-signed ECDSA P-256 certificate made once, which is also the only CA a
// client certificate may come from.

#include <openssl/evp.h>
#include <openssl/x509.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "fuzz/fuzz_check.hpp"
#include "tls/memory_session.hpp"
#include "tls/server_credentials.hpp"

namespace {

using namespace unima::tls;
using Status = MemorySession::Status;

SSL_CTX* make_context() {
  EVP_PKEY* key = EVP_EC_gen("P-256");
  X509* certificate = X509_new();
  ASN1_INTEGER_set(X509_get_serialNumber(certificate), 1);
  X509_gmtime_adj(X509_getm_notBefore(certificate), 0);
  X509_gmtime_adj(X509_getm_notAfter(certificate), 365L * 24 * 3600);
  X509_set_pubkey(certificate, key);
  X509_NAME_add_entry_by_txt(X509_get_subject_name(certificate), "CN", MBSTRING_ASC,
                             reinterpret_cast<const unsigned char*>("fuzz"), -1, -1, 0);
  X509_set_issuer_name(certificate, X509_get_subject_name(certificate));
  X509_sign(certificate, key, EVP_sha256());
  SSL_CTX* context = SSL_CTX_new(TLS_server_method());
  apply_server_policy(context);
  SSL_CTX_use_certificate(context, certificate);
  SSL_CTX_use_PrivateKey(context, key);
  X509_STORE_add_cert(SSL_CTX_get_cert_store(context), certificate);
  SSL_CTX_set_verify(context, SSL_VERIFY_PEER | SSL_VERIFY_FAIL_IF_NO_PEER_CERT, nullptr);
  X509_free(certificate);
  EVP_PKEY_free(key);
  return context;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static SSL_CTX* const context = make_context();
  if (size == 0) return 0;
  const std::size_t piece = data[0] == 0 ? size : data[0];
  const std::span<const std::uint8_t> client(data + 1, size - 1);

  MemorySession session(context);
  std::vector<std::uint8_t> to_client;
  std::uint8_t plaintext[97];  // an odd size: the plaintext comes out in pieces
  bool ended = false;
  for (std::size_t at = 0; at < client.size() && !ended; at += piece) {
    session.feed(client.subspan(at, std::min(piece, client.size() - at)));
    if (!session.handshaken()) {
      const auto status = session.handshake();
      session.take_output(to_client);
      if (status == Status::failed) FUZZ_CHECK(!session.error().empty());
      if (status == Status::failed || status == Status::closed) ended = true;
      if (status != Status::done) continue;
    }
    while (!ended) {
      std::size_t n = 0;
      const auto status = session.read(plaintext, n);
      FUZZ_CHECK(n <= sizeof plaintext);
      FUZZ_CHECK(status == Status::done || n == 0);
      if (status == Status::want_input) break;
      if (status != Status::done) {
        if (status == Status::failed) FUZZ_CHECK(!session.error().empty());
        ended = status == Status::failed || status == Status::closed;
        if (status == Status::closed) FUZZ_CHECK(session.close_notify());  // answered, as the port does
        break;
      }
      // Answered like a Modbus request, so the write path runs too.
      FUZZ_CHECK(session.write(std::span(plaintext, n)));
    }
    session.take_output(to_client);
  }
  // A session that failed says nothing more; one that did not may close cleanly once.
  if (!ended && session.handshaken()) FUZZ_CHECK(session.close_notify());
  FUZZ_CHECK(!session.close_notify());
  session.take_output(to_client);
  return 0;
}
