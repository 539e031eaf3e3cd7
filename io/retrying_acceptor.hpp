#pragma once
// Accepts connections one after another on the loop, for the Modbus TCP slave, the feed
// and the status socket. A failed accept (out of descriptors or memory) leaves the
// pending connection in the backlog, so an immediate retry would fail again at once and
// spin: it is logged and retried after a pause.
//
// Lifetime (io/handler_guard): the owner owns the acceptor and this object, and may
// destroy both at any time on the loop's thread after stop(); a handler already queued
// then sees its token invalid and touches nothing.

#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include <spdlog/spdlog.h>

#include "io/handler_guard.hpp"
#include "platform/asio.hpp"

namespace unima::io {

template <typename Acceptor>
class RetryingAcceptor {
 public:
  using Socket = typename Acceptor::protocol_type::socket;
  static constexpr std::chrono::milliseconds retry_after{100};

  /// `what` starts the log line ("modbus tcp", "feed", "status").
  RetryingAcceptor(Acceptor& acceptor, std::string what, std::function<void(Socket)> on_accepted)
      : acceptor_(acceptor), retry_(acceptor.get_executor()), what_(std::move(what)), on_accepted_(std::move(on_accepted)) {}
  RetryingAcceptor(const RetryingAcceptor&) = delete;
  RetryingAcceptor& operator=(const RetryingAcceptor&) = delete;
  ~RetryingAcceptor() { stop(); }

  void start() {
    stopped_ = false;
    accept();
  }
  /// Stops accepting; closing the acceptor is the owner's.
  void stop() {
    stopped_ = true;
    retry_.cancel();
  }

 private:
  void accept() {
    acceptor_.async_accept([this, token = guard_.token()](const boost::system::error_code& ec, Socket socket) {
      if (!HandlerGuard::alive(token) || ec == asio::error::operation_aborted || stopped_) return;
      if (ec) return retry_later(ec);
      on_accepted_(std::move(socket));
      if (HandlerGuard::alive(token) && !stopped_) accept();
    });
  }

  void retry_later(const boost::system::error_code& ec) {
    spdlog::warn("{}: accept failed: {}; retrying in {} ms", what_, ec.message(), retry_after.count());
    retry_.expires_after(retry_after);
    retry_.async_wait([this, token = guard_.token()](const boost::system::error_code& wait_ec) {
      if (HandlerGuard::alive(token) && !wait_ec && !stopped_) accept();
    });
  }

  Acceptor& acceptor_;
  asio::steady_timer retry_;
  std::string what_;
  std::function<void(Socket)> on_accepted_;
  HandlerGuard guard_;
  bool stopped_ = true;
};

}  // namespace unima::io
