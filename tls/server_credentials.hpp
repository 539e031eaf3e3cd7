#pragma once
// What Modbus/TCP Security's server side is made of (SPEC §11, the Modbus Organization's
// "MB/TCP Security"), on OpenSSL alone: the credentials a TLS port serves with, and who a
// verified client is. The daemon hands the context to tls::MemorySession (Modbus/TCP
// Security) and to Asio's SSL stream (HTTPS, io/tls_context); `unima-bridge check` loads
// the same files the same way, so it accepts what the daemon accepts.
//
// TLS 1.2 and 1.3 only; a client must present a certificate signed by the configured CA,
// else the handshake fails. The client's role is the UTF8String of its certificate's
// extension 1.3.6.1.4.1.50316.802.1; what a role may write is the config's (modbus.tls.roles).

#include <openssl/ssl.h>

#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace unima::tls {

/// The PEM files of modbus.tls (or http.tls, which has no `ca`).
struct TlsFiles {
  std::string certificate;  // the server's certificate, with its chain
  std::string key;          // its private key
  std::string ca;           // the CA(s) that sign clients' certificates; empty: clients need none
  bool operator==(const TlsFiles&) const = default;
};

struct ContextDeleter {
  void operator()(SSL_CTX* context) const { SSL_CTX_free(context); }
};
using ContextPtr = std::unique_ptr<SSL_CTX, ContextDeleter>;

/// What every server context of the daemon allows (SPEC §11): TLS 1.2 and 1.3, TLS 1.2
/// only with ECDHE and an AEAD, no compression, no renegotiation, no session tickets or
/// cache. Throws std::runtime_error naming `section` when this OpenSSL has no such suite.
/// load_server_credentials applies it; the unit tests and the fuzz target too.
void apply_server_policy(SSL_CTX* context, std::string_view section = "modbus.tls");

/// Reads the files into a server context (apply_server_policy's); throws std::runtime_error naming the key, the
/// file and OpenSSL's reason ("modbus.tls.key /etc/…/server.key: key values mismatch").
/// `section` is the config key the files come from ("modbus.tls", "http.tls").
ContextPtr load_server_credentials(const TlsFiles& files, std::string_view section = "modbus.tls");

/// The Modbus/TCP Security role extension's object identifier.
inline constexpr const char* role_extension_oid = "1.3.6.1.4.1.50316.802.1";

struct ClientIdentity {
  std::optional<std::string> role;  // absent when the certificate carries none (or no UTF8String)
  std::string subject;              // "CN=scada-1,O=Plant", for the log and the monitor
};

/// The identity in the certificate a client presented in a completed handshake.
ClientIdentity client_identity(SSL* ssl);

}  // namespace unima::tls
