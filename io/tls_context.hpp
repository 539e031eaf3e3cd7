#pragma once
// The TLS context a Modbus/TCP Security port serves with (SPEC §11): the credentials of
// tls/server_credentials in the form Asio's SSL stream takes.

#include <memory>

#include "platform/asio_ssl.hpp"
#include "tls/server_credentials.hpp"

namespace unima::io {

/// Throws std::runtime_error naming the key and file that did not load.
std::shared_ptr<asio::ssl::context> make_server_tls_context(const tls::TlsFiles& files,
                                                            std::string_view section = "modbus.tls");

}  // namespace unima::io
