#pragma once
// The daemon's status socket: a unix stream socket that answers every connection with one
// JSON document (the front panel, `unima-bridge status`) and closes it.
//
// Why a socket and not a status file rewritten now and then: the answer is made when
// asked, so it is never stale (the Error LED's 2 s hold is seen as it is), and an idle
// daemon neither wakes up nor writes to the disk for nobody.

#include <functional>
#include <string>

#include "io/retrying_acceptor.hpp"
#include "platform/asio.hpp"

namespace unima::io {

class ControlSocket {
 public:
  using DocumentFn = std::function<std::string()>;

  /// Listens on `path` (creating its directory); a stale socket file is replaced, but a
  /// socket another process still answers on is not. Throws config::PathRefused when the
  /// path names something else than a socket (left as it is), std::runtime_error naming
  /// the path when it cannot listen.
  ControlSocket(asio::io_context& io, std::string path, DocumentFn document);
  ~ControlSocket();

  void start();
  void stop();
  const std::string& path() const { return path_; }

 private:
  void answer(asio::local::stream_protocol::socket socket);

  std::string path_;
  DocumentFn document_;
  asio::local::stream_protocol::acceptor acceptor_;
  RetryingAcceptor<asio::local::stream_protocol::acceptor> accepting_;
  bool stopped_ = false;
};

}  // namespace unima::io
