#include "tls/server_credentials.hpp"

#include <openssl/asn1.h>
#include <openssl/err.h>
#include <openssl/objects.h>
#include <openssl/x509.h>
#include <openssl/x509v3.h>

#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

namespace unima::tls {

namespace {

// OpenSSL's reason for the last failure, its queue emptied for the next one.
std::string openssl_reason() {
  const unsigned long error = ERR_peek_last_error();
  std::string reason = error != 0 && ERR_reason_error_string(error) ? ERR_reason_error_string(error) : "cannot be read";
  // A missing file shows as "system lib" with the errno in the library's part.
  if (ERR_GET_LIB(error) == ERR_LIB_SYS) reason = std::strerror(ERR_GET_REASON(error));
  ERR_clear_error();
  return reason;
}

void expect(bool loaded, std::string_view section, const char* key, const std::string& file) {
  if (!loaded) throw std::runtime_error(fmt::format("{}.{} {}: {}", section, key, file, openssl_reason()));
}

std::string one_line(X509_NAME* name) {
  if (name == nullptr) return "?";
  BIO* bio = BIO_new(BIO_s_mem());
  X509_NAME_print_ex(bio, name, 0, XN_FLAG_RFC2253);
  char* data = nullptr;
  const long size = BIO_get_mem_data(bio, &data);
  std::string text(data, static_cast<std::size_t>(size));
  BIO_free(bio);
  return text;
}

}  // namespace

void apply_server_policy(SSL_CTX* context, std::string_view section) {
  // MB/TCP Security requires TLS 1.2 or later.
  SSL_CTX_set_min_proto_version(context, TLS1_2_VERSION);
  // TLS 1.2 with forward secrecy and an AEAD only (TLS 1.3's suites are all AEAD): no CBC
  // with its MAC-then-encrypt, no SHA-1 MAC, no RSA key exchange (SPEC §11).
  if (SSL_CTX_set_cipher_list(context, "ECDHE+AESGCM:ECDHE+CHACHA20") != 1)
    throw std::runtime_error(fmt::format("{}: this OpenSSL offers no ECDHE suite with AES-GCM or ChaCha20: {}", section,
                                         openssl_reason()));
  // No renegotiation: a TLS 1.2 client cannot start a second handshake in the middle of its requests.
  // No session tickets, in either version (SSL_OP_NO_TICKET: TLS 1.2's; num_tickets: TLS
  // 1.3's): Modbus masters keep their connection for hours, so resumption would save
  // little, while tickets cost every full handshake two encryptions and a write and put a
  // ticket key in the process that decrypts every ticket it ever issued.
  SSL_CTX_set_options(context, SSL_OP_NO_COMPRESSION | SSL_OP_CIPHER_SERVER_PREFERENCE | SSL_OP_NO_RENEGOTIATION |
                                   SSL_OP_NO_TICKET);
  SSL_CTX_set_num_tickets(context, 0);
  SSL_CTX_set_session_cache_mode(context, SSL_SESS_CACHE_OFF);
  // Key exchange on X25519, P-256 or P-384 only. OpenSSL's defaults also take the finite-field
  // groups up to ffdhe8192, whose every handshake step costs the server up to a tenth of a
  // second: a lever for one host to keep the handshake worker busy within its rate.
  if (SSL_CTX_set1_groups_list(context, "X25519:P-256:P-384") != 1)
    throw std::runtime_error(fmt::format("{}: this OpenSSL offers none of X25519, P-256, P-384: {}", section, openssl_reason()));
}

ContextPtr load_server_credentials(const TlsFiles& files, std::string_view section) {
  ERR_clear_error();
  ContextPtr context(SSL_CTX_new(TLS_server_method()));
  if (!context) throw std::runtime_error(fmt::format("{}: OpenSSL cannot make a context: {}", section, openssl_reason()));
  apply_server_policy(context.get(), section);
  expect(SSL_CTX_use_certificate_chain_file(context.get(), files.certificate.c_str()) == 1, section, "certificate",
         files.certificate);
  expect(SSL_CTX_use_PrivateKey_file(context.get(), files.key.c_str(), SSL_FILETYPE_PEM) == 1, section, "key", files.key);
  expect(SSL_CTX_check_private_key(context.get()) == 1, section, "key", files.key);
  if (files.ca.empty()) return context;  // a browser: no client certificate asked for
  expect(SSL_CTX_load_verify_locations(context.get(), files.ca.c_str(), nullptr) == 1, section, "ca", files.ca);
  // The CA's names go into the CertificateRequest, so a client with several certificates
  // picks one this server trusts.
  if (auto* names = SSL_load_client_CA_file(files.ca.c_str())) SSL_CTX_set_client_CA_list(context.get(), names);
  SSL_CTX_set_verify(context.get(), SSL_VERIFY_PEER | SSL_VERIFY_FAIL_IF_NO_PEER_CERT, nullptr);
  return context;
}

ClientIdentity client_identity(SSL* ssl) {
  ClientIdentity identity;
  X509* certificate = SSL_get1_peer_certificate(ssl);
  if (certificate == nullptr) return identity;
  identity.subject = one_line(X509_get_subject_name(certificate));
  ASN1_OBJECT* oid = OBJ_txt2obj(role_extension_oid, 1);
  const int at = oid ? X509_get_ext_by_OBJ(certificate, oid, -1) : -1;
  if (at >= 0) {
    // The extension's value is the DER of a UTF8String.
    const ASN1_OCTET_STRING* data = X509_EXTENSION_get_data(X509_get_ext(certificate, at));
    const unsigned char* der = ASN1_STRING_get0_data(data);
    ASN1_UTF8STRING* role = d2i_ASN1_UTF8STRING(nullptr, &der, ASN1_STRING_length(data));
    if (role != nullptr) {
      identity.role = std::string(reinterpret_cast<const char*>(ASN1_STRING_get0_data(role)),
                                  static_cast<std::size_t>(ASN1_STRING_length(role)));
      ASN1_UTF8STRING_free(role);
    }
  }
  ASN1_OBJECT_free(oid);
  X509_free(certificate);
  return identity;
}

}  // namespace unima::tls
