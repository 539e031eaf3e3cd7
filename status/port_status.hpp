#pragma once
// A Modbus port's entry in the status document's "ports" (tcp, tls, rtu, master): its
// transactions by monitor state, its clients and, for a TLS port, its handshakes — which
// HTTPS reports too, as "http.handshakes". Here rather than in modbus/, which takes no JSON.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "modbus/transaction_counters.hpp"
#include "status/statistic.hpp"

namespace unima::status {

/// A TLS port's handshakes (tls::HandshakeLimiter's counters).
struct HandshakeStatus {
  std::uint64_t completed = 0;
  std::uint64_t failed = 0;
  std::uint64_t in_progress = 0;
  std::map<std::string, std::uint64_t> refused;  // by the limit that refused (HandshakeLimiter::name)
};
void to_json(nlohmann::json& j, const HandshakeStatus& s);
void from_json(const nlohmann::json& j, HandshakeStatus& s);

struct PortStatus {
  std::string port;  // "tcp", "tls", "rtu", "master"
  std::uint64_t transactions = 0;
  std::map<std::string, std::uint64_t> states;  // by monitor state ("Done", "Err02", ...), each a key of its own
  std::optional<std::string> listen;            // a listening port's "address:port"
  std::optional<std::uint64_t> clients;         // a listening port's connections
  std::optional<HandshakeStatus> handshakes;    // a TLS port's
};
/// Absent listen, clients and handshakes are left out of the entry, not null.
void to_json(nlohmann::json& j, const PortStatus& s);
void from_json(const nlohmann::json& j, PortStatus& s);

/// A port's transactions as the monitor counts them, every state named.
PortStatus port_status(const char* port, const modbus::TransactionCounters& counters);

/// A TLS port's handshakes with the port they are labelled by ("tls", or "https").
struct PortHandshakes {
  std::string port;
  HandshakeStatus handshakes;
};

const std::vector<Statistic<PortStatus>>& port_statistics();
const std::vector<Statistic<PortHandshakes>>& handshake_statistics();

}  // namespace unima::status
