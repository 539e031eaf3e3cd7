#pragma once
// The server side of Modbus/TCP Security (SPEC §11, the Modbus Organization's "MB/TCP
// Security"): the TLS context a port serves with, and who a verified client is.
//
// TLS 1.2 and 1.3 only; a client must present a certificate signed by the configured CA,
// else the handshake fails. The client's role is the UTF8String of its certificate's
// extension 1.3.6.1.4.1.50316.802.1; what a role may write is the config's (modbus.tls.roles).

#include <memory>
#include <optional>
#include <string>

#include "platform/asio_ssl.hpp"

namespace unima::io {

/// The PEM files of modbus.tls.
struct TlsFiles {
  std::string certificate;  // the server's certificate, with its chain
  std::string key;          // its private key
  std::string ca;           // the CA(s) that sign clients' certificates
  bool operator==(const TlsFiles&) const = default;
};

/// Reads the files; throws std::runtime_error naming the key, the file and OpenSSL's
/// reason ("modbus.tls.key /etc/…/server.key: no such file", "… does not match the
/// certificate").
std::shared_ptr<asio::ssl::context> make_server_tls_context(const TlsFiles& files);

/// The Modbus/TCP Security role extension's object identifier.
inline constexpr const char* role_extension_oid = "1.3.6.1.4.1.50316.802.1";

struct ClientIdentity {
  std::optional<std::string> role;  // absent when the certificate carries none (or no UTF8String)
  std::string subject;              // "CN=scada-1,O=Plant" style, for the log and monitor
};

/// The identity in the certificate a client presented in a completed handshake.
ClientIdentity client_identity(SSL* ssl);

}  // namespace unima::io
