#pragma once
// Accepts connections one after another on the loop, for the Modbus TCP slave, the feed
// and the status socket. A failed accept (out of descriptors or memory) leaves the
// pending connection in the backlog, so an immediate retry would fail again at once and
// spin: it is logged and retried after a pause — unless, out of descriptors, the owner
// can make room (the Modbus TCP slave closes its longest-idle client, SPEC §10), and then
// it accepts again at once.
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
  /// `make_room`, when given, is asked to free a descriptor when there is none left; it
  /// returns false when it cannot.
  RetryingAcceptor(Acceptor& acceptor, std::string what, std::function<void(Socket)> on_accepted,
                   std::function<bool()> make_room = {})
      : acceptor_(acceptor), retry_(acceptor.get_executor()), what_(std::move(what)), on_accepted_(std::move(on_accepted)),
        make_room_(std::move(make_room)) {}
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
      if (ec && out_of_descriptors(ec) && make_room_ && make_room_()) return accept();
      if (ec) return retry_later(ec);
      on_accepted_(std::move(socket));
      if (HandlerGuard::alive(token) && !stopped_) accept();
    });
  }

  static bool out_of_descriptors(const boost::system::error_code& ec) {
    return ec == asio::error::no_descriptors || ec == boost::system::errc::too_many_files_open_in_system;
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
  std::function<bool()> make_room_;
  HandlerGuard guard_;
  bool stopped_ = true;
};

}  // namespace unima::io
