#pragma once
// The `feed` UnimaBUS transport (SPEC §6): external drivers connect over TCP (host:port) or
// a unix socket (unix:/path) and exchange JSON lines. Each client gets a snapshot of what
// the bridge publishes on connect, then every change; its telegrams update the banks.

#include <functional>
#include <memory>
#include <set>
#include <string>

#include "config/endpoint.hpp"
#include "io/connection_set.hpp"
#include "io/retrying_acceptor.hpp"
#include "platform/asio.hpp"
#include "unimabus/transport.hpp"

namespace unima::io {

class FeedTransport final : public unimabus::Transport {
 public:
  /// The lines a new client gets first: one per published register.
  using SnapshotFn = std::function<std::string()>;

  /// Binds at once; throws boost::system::system_error when it cannot, and
  /// config::PathRefused when a unix socket's path names something else than a socket
  /// (never removed). At most `max_clients` are served at once; more are told so and closed.
  FeedTransport(asio::io_context& io, const config::ListenEndpoint& listen, unsigned max_clients,
                unimabus::TelegramHandler on_telegram, SnapshotFn snapshot);
  ~FeedTransport() override;

  void start() override;
  void stop() override;
  void publish(banks::BankId bank, std::uint16_t offset, std::uint16_t value) override;
  std::optional<std::size_t> clients() const override { return sessions_.size(); }

  const std::string& listen() const { return listen_; }
  /// The TCP port actually bound, 0 for a unix socket.
  std::uint16_t port() const;

  class Session;

 private:
  template <typename Socket>
  void accepted(Socket socket);
  void adopt(std::shared_ptr<Session> session);
  void forget(Session* session);

  asio::io_context& io_;
  std::string listen_;
  unsigned max_clients_;
  std::uint64_t refused_ = 0;  // since the limit was last reached; logged once per episode
  unimabus::TelegramHandler on_telegram_;
  SnapshotFn snapshot_;
  std::unique_ptr<asio::ip::tcp::acceptor> tcp_acceptor_;
  std::unique_ptr<asio::local::stream_protocol::acceptor> unix_acceptor_;
  std::string unix_path_;
  ConnectionSet<Session> sessions_;
  std::unique_ptr<RetryingAcceptor<asio::ip::tcp::acceptor>> tcp_accepting_;
  std::unique_ptr<RetryingAcceptor<asio::local::stream_protocol::acceptor>> unix_accepting_;
  bool stopped_ = false;
};

}  // namespace unima::io
