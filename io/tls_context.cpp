#include "io/tls_context.hpp"

#include <openssl/asn1.h>
#include <openssl/objects.h>
#include <openssl/ssl.h>
#include <openssl/x509.h>
#include <openssl/x509v3.h>

#include <stdexcept>

#include <fmt/format.h>

namespace unima::io {

namespace {

template <typename Load>
void load(const char* key, const std::string& file, Load&& load_it) {
  boost::system::error_code ec;
  load_it(ec);
  if (ec) throw std::runtime_error(fmt::format("modbus.tls.{} {}: {}", key, file, ec.message()));
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

std::shared_ptr<asio::ssl::context> make_server_tls_context(const TlsFiles& files) {
  auto context = std::make_shared<asio::ssl::context>(asio::ssl::context::tls_server);
  // MB/TCP Security requires TLS 1.2 or later.
  SSL_CTX_set_min_proto_version(context->native_handle(), TLS1_2_VERSION);
  context->set_options(asio::ssl::context::default_workarounds | asio::ssl::context::no_compression |
                       asio::ssl::context::single_dh_use);
  load("certificate", files.certificate, [&](auto& ec) { context->use_certificate_chain_file(files.certificate, ec); });
  load("key", files.key, [&](auto& ec) { context->use_private_key_file(files.key, asio::ssl::context::pem, ec); });
  if (SSL_CTX_check_private_key(context->native_handle()) != 1)
    throw std::runtime_error(fmt::format("modbus.tls.key {}: does not match the certificate {}", files.key,
                                         files.certificate));
  load("ca", files.ca, [&](auto& ec) { context->load_verify_file(files.ca, ec); });
  // The CA's names are sent in the CertificateRequest, so a client with several
  // certificates picks one this server trusts.
  if (auto* names = SSL_load_client_CA_file(files.ca.c_str())) SSL_CTX_set_client_CA_list(context->native_handle(), names);
  context->set_verify_mode(asio::ssl::verify_peer | asio::ssl::verify_fail_if_no_peer_cert);
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

}  // namespace unima::io
