#pragma once
// The read-only HTTP/1.1 server of SPEC §13 (/metrics, /healthz, /api/…) on Boost.Beast,
// on the daemon's event loop. What a path answers is the Bridge's (a handler); this owns
// the sockets and the limits a technician's browser or a scraper must live with: request
// headers up to 8 KiB and no body, a deadline for each request (an idle keep-alive
// connection is closed by it too), and at most `max_clients` connections — one more
// closes the one idle the longest (SPEC §10's slow-client rules).

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <string_view>

#include "io/retrying_acceptor.hpp"
#include "platform/asio.hpp"

namespace unima::io {

struct HttpOptions {
  std::string listen = "127.0.0.1";
  std::uint16_t port = 8080;
  unsigned max_clients = 16;
  std::chrono::milliseconds request_timeout{10'000};  // from the end of one answer to the end of the next request
};

struct HttpResponse {
  unsigned status = 200;
  std::string content_type = "text/plain; charset=utf-8";
  std::string body;
};

/// Answers a GET (or HEAD) of `target` (the path and query as sent).
using HttpHandler = std::function<HttpResponse(std::string_view target)>;

class HttpServer {
 public:
  /// Binds at once; throws boost::system::system_error when it cannot.
  HttpServer(asio::io_context& io, const HttpOptions& options, HttpHandler handler);
  ~HttpServer();

  void start();
  void stop();
  std::uint16_t port() const;
  std::size_t client_count() const { return connections_.size(); }
  void set_handler(HttpHandler handler) { handler_ = std::move(handler); }

  class Connection;

 private:
  void adopt(asio::ip::tcp::socket socket);
  void forget(Connection* connection);

  HttpOptions options_;
  HttpHandler handler_;
  asio::ip::tcp::acceptor acceptor_;
  RetryingAcceptor<asio::ip::tcp::acceptor> accepting_;
  std::set<std::shared_ptr<Connection>> connections_;
  bool stopped_ = false;
};

}  // namespace unima::io
