#pragma once
// The HTTP/1.1 server of SPEC §13 (/, /metrics, /healthz, /api/…) on Boost.Beast, on the
// daemon's event loop, plain or over TLS (Asio's SSL stream). What a path answers, and who
// may ask, is the Bridge's (a handler, a gate); this owns the sockets and the limits a
// technician's browser or a scraper must live with: request headers up to 8 KiB, no body
// but a PUT's or POST's up to `max_body` (a config sent to /api/config, SPEC §19; 413
// beyond, before it is read), a deadline for each request (and for the TLS handshake; an idle keep-alive
// connection is closed by it too), and at most `max_clients` connections — one more
// closes one that web::connection_to_evict chooses (never one with a request in
// progress; one of the host holding the most), or is closed itself when each has a
// request in progress (SPEC §10's slow-client rules, issue 43).

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "web/event_sink.hpp"
#include "io/connection_set.hpp"
#include "io/retrying_acceptor.hpp"
#include "platform/asio_ssl.hpp"
#include "tls/handshake_limiter.hpp"

namespace unima::io {

struct HttpOptions {
  std::string listen = "127.0.0.1";
  std::uint16_t port = 8080;
  unsigned max_clients = 16;
  std::chrono::milliseconds request_timeout{10'000};  // from the end of one answer to the end of the next request
  std::shared_ptr<asio::ssl::context> tls;  // HTTPS; null: plain HTTP
  // HTTPS: the handshakes a host may start (io/handshake_admission), the service's across reloads.
  std::shared_ptr<tls::HandshakeLimiter> handshakes;
  std::string port_origin;  // the config's "file:line:col" of http.port, named when the port is taken
  std::size_t max_body = 0;  // a PUT's or POST's body at most (413 beyond); GET and HEAD carry none
};

/// The content type of every plain-text answer (errors, refusals, /healthz).
inline constexpr const char* plain_text_type = "text/plain; charset=utf-8";

struct HttpResponse;
/// Gives a deferred answer (HttpResponse::later); called once, from the loop. After the
/// client went (or the server stopped) it does nothing.
using HttpReply = std::function<void(HttpResponse)>;

struct HttpResponse {
  unsigned status = 200;
  std::string content_type = plain_text_type;
  std::string body;
  /// Extra header fields, e.g. Content-Security-Policy for the page.
  std::vector<std::pair<std::string, std::string>> headers;
  /// Set for an event stream: after the header (200, text/event-stream) the connection
  /// stays open and this is called with its sink; `body` is ignored. A HEAD gets the header only.
  std::function<void(std::shared_ptr<web::EventSink>)> stream;
  /// Set for an answer that comes when a long task ends (a config's probe, up to minutes):
  /// called at once with how to reply; the connection waits for it with no deadline, and is
  /// closed when its client goes meanwhile. The other fields are ignored.
  std::function<void(HttpReply)> later;
};

/// A request as the handler sees it, once the gate let it through.
struct HttpRequest {
  std::string_view method;  // "GET", "HEAD", "PUT" or "POST"
  std::string_view target;  // the path and query as sent
  std::string_view body;    // a PUT's or POST's
  std::string user;         // the user of http.users who sent it; empty when the server asks no one
  std::string peer;         // "address:port"
  bool tls = false;         // it came over HTTPS
  bool from_another_site = false;  // a browser made it for another site's page (web/request_origin)
};

/// Answers a request.
using HttpHandler = std::function<HttpResponse(const HttpRequest& request)>;

/// The gate's verdict on a request: nullopt lets it through, as `user` (empty when the
/// server asks no one); a response (401, 429, 503) goes instead.
using HttpGateDone = std::function<void(std::optional<HttpResponse> refusal, std::string user)>;
/// Called when a connection goes while the gate has its `done` (the client left, the
/// server stopped, closed): `done` must then never run, and what it waited for is let go.
using HttpGateLeave = std::function<void()>;
/// Asked before every request is answered, with its Authorization header (empty when
/// none) and the peer; calls `done` at once or later, from the loop (a password check is
/// computed elsewhere). The connection waits for it, reading nothing more, but sees its
/// client leave. Returns how to leave when `done` is kept for later; empty when it ran.
using HttpGate = std::function<HttpGateLeave(std::string_view authorization, const std::string& peer, HttpGateDone done)>;

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
  void set_gate(HttpGate gate) { gate_ = std::move(gate); }
  /// New connections shake hands with `tls` (renewed certificates); open ones keep theirs.
  void set_tls_context(std::shared_ptr<asio::ssl::context> tls) { options_.tls = std::move(tls); }
  bool tls() const { return options_.tls != nullptr; }
  const HttpOptions& options() const { return options_; }

  class ConnectionBase;
  template <class Stream>
  class Connection;

 private:
  void adopt(asio::ip::tcp::socket socket);
  /// Full: the connection that web::connection_to_evict chooses to close; null when none may go.
  std::shared_ptr<ConnectionBase> connection_to_evict() const;
  void forget(ConnectionBase* connection);

  HttpOptions options_;
  HttpHandler handler_;
  HttpGate gate_;
  asio::ip::tcp::acceptor acceptor_;
  RetryingAcceptor<asio::ip::tcp::acceptor> accepting_;
  ConnectionSet<ConnectionBase> connections_;
  bool stopped_ = false;
};

}  // namespace unima::io
