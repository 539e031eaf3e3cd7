#pragma once
// Modbus TCP slave on Boost.Asio (SPEC §3): many clients at once, pipelined requests
// answered in order (the answers to one read go out in one write), unit-id rules, an idle
// time-out and a connection limit. A client that sends a bad MBAP header loses only its
// own connection.

#include <chrono>
#include <cstdint>
#include <memory>
#include <set>
#include <string>

#include "platform/asio.hpp"
#include "io/retrying_acceptor.hpp"
#include "io/slave_context.hpp"

namespace unima::io {

struct TcpSlaveOptions {
  std::string listen = "0.0.0.0";
  std::uint16_t port = 502;
  unsigned max_clients = 128;
  std::chrono::milliseconds idle_timeout{60'000};  // 0: never
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
  void set_limits(unsigned max_clients, std::chrono::milliseconds idle_timeout) {
    options_.max_clients = max_clients;
    options_.idle_timeout = idle_timeout;
  }
  const TcpSlaveOptions& options() const { return options_; }
  /// The port actually bound (differs from options().port when that was 0).
  std::uint16_t port() const;
  std::size_t client_count() const { return connections_.size(); }

  class Connection;

 private:
  void adopt(asio::ip::tcp::socket socket);
  void forget(Connection* connection);

  asio::io_context& io_;
  TcpSlaveOptions options_;
  SlaveContext context_;
  asio::ip::tcp::acceptor acceptor_;
  RetryingAcceptor<asio::ip::tcp::acceptor> accepting_;
  std::set<std::shared_ptr<Connection>> connections_;
  bool stopped_ = false;
};

}  // namespace unima::io
