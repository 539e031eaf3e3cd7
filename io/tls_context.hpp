#pragma once
// The TLS contexts the bridge's servers serve with — Modbus/TCP Security (SPEC §11) and
// HTTPS: the credentials of tls/server_credentials in the form Asio's SSL stream takes.

#include <cstddef>
#include <memory>
#include <string_view>

#include "config/config.hpp"
#include "platform/asio_ssl.hpp"
#include "tls/server_credentials.hpp"

namespace unima::io {

/// The files each section names.
tls::TlsFiles modbus_tls_files(const config::TlsSlaveConfig& tls);
tls::TlsFiles http_tls_files(const config::HttpTlsConfig& tls);

/// Throws std::runtime_error naming the key and file that did not load. Takes the context
/// prepare_server_tls_contexts built for the same files when none of them changed since.
std::shared_ptr<asio::ssl::context> make_server_tls_context(const tls::TlsFiles& files,
                                                            std::string_view section = "modbus.tls");

/// Builds the contexts `next` will serve with (modbus.tls, http.tls), for
/// make_server_tls_context to take when a reload stages `next`: reading the certificate
/// and key is about a millisecond of OpenSSL, which this does on the caller's thread (a
/// change from afar: the coordinator's worker) instead of on the event loop. Thread-safe;
/// files that do not load are left for the stage to report. Keeps the last few only.
void prepare_server_tls_contexts(const config::Config& next);

/// How many contexts make_server_tls_context took ready so far (for the tests).
std::size_t prepared_tls_contexts_taken();

}  // namespace unima::io
