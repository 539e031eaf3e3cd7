#pragma once
// The daemon's control socket: a unix stream socket that answers a connection with one
// JSON document (the front panel, `unima-bridge status`) and closes it — or, when the
// client sends a request line first (`unima-bridge config …`), with the answer to it.
//
// A client that only reads gets the status after `request_grace` without a byte from it:
// the status readers of every version (the CLI, scripts with socat) keep working
// unchanged. A client with a request writes it at once after connect; one that lost the
// race against the grace reads a status document, and tries again.
//
// Why a socket and not a status file rewritten now and then: the answer is made when
// asked, so it is never stale (the Error LED's 2 s hold is seen as it is), and an idle
// daemon neither wakes up nor writes to the disk for nobody.

#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "io/retrying_acceptor.hpp"
#include "platform/asio.hpp"

namespace unima::io {

/// A request line and who sent it (SO_PEERCRED: the kernel's word, not the client's).
struct ControlRequest {
  std::string line;
  unsigned uid = 0;
  int pid = 0;
};

class ControlSocket {
 public:
  using DocumentFn = std::function<std::string()>;
  using Reply = std::function<void(std::string)>;
  /// Answers a request by calling the reply once, at once or later (a config's probe).
  using RequestFn = std::function<void(ControlRequest, Reply)>;

  static constexpr std::chrono::milliseconds request_grace{20};
  static constexpr std::size_t max_request_bytes = 1024 * 1024;  // a 256 KiB config, escaped in JSON

  /// Listens on `path` (creating its directory); a stale socket file is replaced, but a
  /// socket another process still answers on is not. Throws config::PathRefused when the
  /// path names something else than a socket (left as it is), std::runtime_error naming
  /// the path when it cannot listen.
  ControlSocket(asio::io_context& io, std::string path, DocumentFn document, RequestFn request = {});
  ~ControlSocket();

  void start();
  void stop();
  const std::string& path() const { return path_; }

 private:
  struct Connection;
  void accepted(asio::local::stream_protocol::socket socket);
  static void answer_status(const std::shared_ptr<Connection>& connection);
  static void read_request(const std::shared_ptr<Connection>& connection);

  std::string path_;
  DocumentFn document_;
  RequestFn request_;
  asio::local::stream_protocol::acceptor acceptor_;
  RetryingAcceptor<asio::local::stream_protocol::acceptor> accepting_;
  bool stopped_ = false;
};

}  // namespace unima::io
