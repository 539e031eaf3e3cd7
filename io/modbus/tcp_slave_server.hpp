#pragma once
// Modbus TCP slave on Boost.Asio (SPEC §3): many clients at once, pipelined requests
// answered in order (the answers to one read go out in one write), unit-id rules, an idle
// time-out, a deadline for a started request and a connection limit at which a new client
// takes the place of the one idle the longest (SPEC §10). A client that sends a bad MBAP
// header loses only its own connection.
//
// The same server speaks Modbus/TCP Security (SPEC §11) when given a TLS context: each
// client's handshake must complete within frame_timeout, its certificate's role says what
// it may write, and everything else — limits, eviction, the allow list — is the same. A
// client whose host starts more handshakes than tls::HandshakeLimiter allows is closed at
// accept, before it costs any cryptography or another client's slot.

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>

#include "config/peer_allow_list.hpp"
#include "modbus/write_rights.hpp"
#include "platform/asio_ssl.hpp"
#include "tls/handshake_limiter.hpp"
#include "io/connection_set.hpp"
#include "io/cpu_worker.hpp"
#include "io/retrying_acceptor.hpp"
#include "io/modbus/slave_context.hpp"

namespace unima::io {

/// Modbus/TCP Security: what a TLS port serves with.
struct TlsSlaveSetup {
  std::shared_ptr<asio::ssl::context> context;
  std::map<std::string, modbus::WriteRights> roles;  // a role not listed may write nothing
  std::shared_ptr<tls::HandshakeLimiter> handshakes;  // the port's, across reloads
  std::shared_ptr<CpuWorker> handshake_worker;        // where handshakes are computed (tls_connection.cpp)
};

struct TcpSlaveOptions {
  std::string listen = "0.0.0.0";
  std::uint16_t port = 502;
  unsigned max_clients = 128;
  std::chrono::milliseconds idle_timeout{60'000};  // 0: never
  std::chrono::milliseconds frame_timeout{2'000};  // a started ADU must be complete within it
  config::PeerAllowList allow;  // who may connect; empty: anyone (SPEC §11)
  bool read_only = false;       // every write answered with exception 01
  std::optional<TlsSlaveSetup> tls;  // set: Modbus/TCP Security
};

class TcpSlaveServer {
 public:
  /// Binds at once; throws boost::system::system_error when the address is taken or bad.
  TcpSlaveServer(asio::io_context& io, const TcpSlaveOptions& options, const SlaveContext& context);
  ~TcpSlaveServer();

  void start();
  void stop();
  void set_context(const SlaveContext& context) { context_ = context; }
  /// Applies to new clients and to the idle checks from now on.
  void set_limits(unsigned max_clients, std::chrono::milliseconds idle_timeout, std::chrono::milliseconds frame_timeout) {
    options_.max_clients = max_clients;
    options_.idle_timeout = idle_timeout;
    options_.frame_timeout = frame_timeout;
  }
  /// Applies to every request from now on (read_only) and to the clients: those the new
  /// list leaves out are disconnected.
  void set_access(const config::PeerAllowList& allow, bool read_only);
  /// A TLS port's new context (renewed certificates) serves the handshakes from now on;
  /// its roles apply to every request from now on.
  void set_tls(const TlsSlaveSetup& tls) { options_.tls = tls; }
  /// "modbus tcp" or "modbus tls": the log's name of this port.
  const char* name() const { return options_.tls ? "modbus tls" : "modbus tcp"; }
  /// The kind of a warning a client causes, per port ("modbus tls: bad MBAP headers").
  std::string warning(std::string_view what) const { return std::string(name()) + ": " + std::string(what); }
  const TcpSlaveOptions& options() const { return options_; }
  /// The port actually bound (differs from options().port when that was 0).
  std::uint16_t port() const;
  std::size_t client_count() const { return connections_.size(); }

  class Connection;

 private:
  void adopt(asio::ip::tcp::socket socket);
  void forget(Connection* connection);
  /// Closes the connection idle the longest, for a new client; false when there is none.
  bool evict_longest_idle(const std::string& why);
  /// Frees a descriptor for a pending client when the process has none left: the
  /// longest-idle connection's, or the reserve's. False when neither is there.
  bool make_room();
  /// False (and logged, rate-limited) when modbus.tcp.allow does not list the peer.
  bool allowed(const asio::ip::address& address, const std::string& peer) const;
  /// What a client of this port may write, to the banks and through the gateway: nothing
  /// when this port or the bridge is read only; on a TLS port what its role may (nothing
  /// without one); nullptr: everything.
  const modbus::WriteRights* write_rights(const std::optional<std::string>& role) const;

  asio::io_context& io_;
  TcpSlaveOptions options_;
  SlaveContext context_;
  asio::ip::tcp::acceptor acceptor_;
  RetryingAcceptor<asio::ip::tcp::acceptor> accepting_;
  ConnectionSet<Connection> connections_;
  bool stopped_ = false;
  // A descriptor held back (/dev/null) so that accept never starves when the process
  // runs out of them: given up for a client, taken back when one is free again.
  int reserve_fd_ = -1;
  const modbus::WriteRights nothing_ = modbus::WriteRights::nothing();
  // Warnings about clients (evictions, deadlines, bad headers) at most once a minute.
};

/// The peer's address in the form of modbus.tcp.allow and modbus.gateway.priority: IPv4
/// as ::ffff:a.b.c.d.
config::PeerAddress peer_address(const asio::ip::address& address);

}  // namespace unima::io
