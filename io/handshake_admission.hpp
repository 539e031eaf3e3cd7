#pragma once
// A TLS port's door: the one place a new connection is weighed against the port's
// tls::HandshakeLimiter (SPEC §11) — by the Modbus/TCP Security port and by HTTPS alike,
// since a handshake costs the event loop the same whichever port it comes in by — and
// the place the limiter's counters become the status document's (and so /metrics').

#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "platform/asio.hpp"
#include "status/port_status.hpp"
#include "tls/handshake_limiter.hpp"

namespace unima::io {

/// A handshake's place for a new connection from `address` ("address:port" `peer`) now,
/// or nullopt (logged once per peer host as "`port_name`: TLS handshakes refused"): the
/// caller closes the connection before OpenSSL sees a byte of it.
std::optional<tls::HandshakeSlot> admit_handshake(const std::shared_ptr<tls::HandshakeLimiter>& limiter,
                                                  const asio::ip::address& address, const std::string& peer,
                                                  std::string_view port_name);

/// The limiter's counters as the status document's TLS port (and HTTPS) holds them.
status::HandshakeStatus handshake_counters(const tls::HandshakeLimiter& limiter);

}  // namespace unima::io
