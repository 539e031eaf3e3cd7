#include "io/http/http_server.hpp"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>

#include <algorithm>
#include <array>
#include <memory>
#include <optional>

#include <spdlog/spdlog.h>

#include "io/handshake_admission.hpp"
#include "platform/beast.hpp"
#include "platform/peer_warnings.hpp"
#include "web/connection_eviction.hpp"
#include "web/request_origin.hpp"

namespace unima::io {

namespace http = beast::http;
using asio::ip::tcp;
using Clock = std::chrono::steady_clock;

namespace {

constexpr std::uint32_t max_header_bytes = 8 * 1024;
// What is read and dropped of a refused body before the close, at most (linger()).
constexpr std::size_t max_lingering_bytes = 1024 * 1024;
constexpr auto max_lingering_time = std::chrono::seconds(1);

using PlainStream = beast::tcp_stream;
using TlsStream = beast::ssl_stream<beast::tcp_stream>;

// After the socket turned readable: whether the client's end came (its FIN or a reset), not
// only bytes. Asked of the kernel, so that nothing is read that the stream (or TLS) must
// read later.
bool client_left(tcp::socket& socket) {
  tcp_info info{};
  socklen_t size = sizeof info;
  if (::getsockopt(socket.native_handle(), IPPROTO_TCP, TCP_INFO, &info, &size) != 0) return true;
  return info.tcpi_state != TCP_ESTABLISHED;
}

}  // namespace

// What the server keeps of a connection, whatever its stream.
class HttpServer::ConnectionBase : public web::EventSink {
 public:
  virtual void start() = 0;
  virtual void close() = 0;
  Clock::time_point last_activity() const { return last_activity_; }
  const std::string& peer() const { return peer_; }
  /// A request read and not yet answered (its gate deciding, its answer being written):
  /// the connection is not idle, whenever it last sent something.
  bool request_in_progress() const { return request_in_progress_; }
  /// An HTTPS connection's place among the handshakes its port allows (tls::HandshakeLimiter).
  void hold(tls::HandshakeSlot handshake) { handshake_ = std::move(handshake); }

 protected:
  std::string peer_;
  tls::HandshakeSlot handshake_;  // until the handshake completes; else its end counts it failed
  Clock::time_point last_activity_ = Clock::now();
  bool request_in_progress_ = false;
};

template <class Stream>
class HttpServer::Connection : public HttpServer::ConnectionBase, public std::enable_shared_from_this<Connection<Stream>> {
 public:
  // A TLS connection's stream is made with the server's context of the moment.
  template <class... Context>
  Connection(HttpServer& server, tcp::socket socket, Context&... context) : server_(server), stream_(std::move(socket), context...) {
    boost::system::error_code ec;
    const auto remote = socket_().remote_endpoint(ec);
    peer_ = ec ? std::string("?") : remote.address().to_string() + ":" + std::to_string(remote.port());
  }

  void start() override {
    if constexpr (std::is_same_v<Stream, TlsStream>) {
      // The handshake is under the request deadline: a client stuck in it is cut like a slow one.
      beast::get_lowest_layer(stream_).expires_after(server_.options_.request_timeout);
      stream_.async_handshake(asio::ssl::stream_base::server, [this, self = this->shared_from_this()](const boost::system::error_code& ec) {
        if (closed_) return;
        if (ec) {
          platform::warn_from_peer("http: TLS handshakes failed", peer_, "http: TLS handshake with {} failed: {}", peer_, ec.message());
          return finish();
        }
        handshake_.completed();
        handshaken_ = true;
        read();
      });
    } else {
      read();
    }
  }
  void close() override {
    closed_ = true;
    // Whatever the gate keeps for this request (a password check and its host's place) goes too.
    if (auto leave = std::exchange(leave_gate_, nullptr)) leave();
    boost::system::error_code ec;
    socket_().shutdown(tcp::socket::shutdown_both, ec);
    socket_().close(ec);
  }

  bool send(std::string_view events) override {
    if (closed_) return false;
    if (queued_.size() + events.size() > max_queued_bytes) {
      platform::warn_from_peer("http: event streams too slow", peer_,
                               "http: {} reads its event stream too slowly ({} bytes waiting): closing it", peer_,
                               queued_.size());
      finish();
      return false;
    }
    queued_.append(events);
    if (!writing_ && streaming_) write_queued();
    return true;
  }
  bool closed() const override { return closed_; }

 private:
  tcp::socket& socket_() { return beast::get_lowest_layer(stream_).socket(); }

  // The header first: a body only a PUT or POST may have, and a Content-Length over
  // max_body is refused (413) before any of it is read.
  void read() {
    parser_.emplace();
    parser_->header_limit(max_header_bytes);
    parser_->body_limit(server_.options_.max_body);
    beast::get_lowest_layer(stream_).expires_after(server_.options_.request_timeout);
    http::async_read_header(stream_, buffer_, *parser_,
                            [this, self = this->shared_from_this()](const boost::system::error_code& ec, std::size_t) {
                              if (closed_) return;
                              if (ec == http::error::end_of_stream || ec == asio::error::eof) return finish();
                              if (ec == beast::error::timeout || ec == asio::ssl::error::stream_truncated) return finish();
                              last_activity_ = Clock::now();
                              request_in_progress_ = true;
                              if (ec) return refuse(ec);
                              const auto method = parser_->get().method();
                              const bool may_have_body = method == http::verb::put || method == http::verb::post;
                              if (!may_have_body && (parser_->chunked() || parser_->content_length().value_or(0) > 0))
                                return refuse(http::error::unexpected_body);
                              if (parser_->is_done()) return answer(parser_->get());
                              continue_then_read_body();
                            });
  }

  // A client that asked to be told to go on (curl does for a body over 1 KiB) is, and then
  // the body is read, under the same deadline.
  void continue_then_read_body() {
    const auto expect = parser_->get()[http::field::expect];
    if (!beast::iequals(expect, "100-continue")) return read_body();
    static constexpr std::string_view go_on = "HTTP/1.1 100 Continue\r\n\r\n";
    asio::async_write(stream_, asio::buffer(go_on.data(), go_on.size()),
                      [this, self = this->shared_from_this()](const boost::system::error_code& ec, std::size_t) {
                        if (closed_) return;
                        if (ec) return finish();
                        read_body();
                      });
  }

  void read_body() {
    http::async_read(stream_, buffer_, *parser_, [this, self = this->shared_from_this()](const boost::system::error_code& ec, std::size_t) {
      if (closed_) return;
      if (ec == beast::error::timeout || ec == asio::ssl::error::stream_truncated || ec == asio::error::eof) return finish();
      if (ec) return refuse(ec);
      last_activity_ = Clock::now();
      answer(parser_->get());
    });
  }

  // A request the parser refused (headers over 8 KiB, a body too large or where none may
  // be, garbage) gets 400, 413 or 431, once, and the connection closes: the stream cannot
  // be trusted after it.
  void refuse(const boost::system::error_code& ec) {
    platform::warn_from_peer("http: bad requests", peer_, "http: {} sent a bad request: {}", peer_, ec.message());
    const auto status = ec == http::error::header_limit ? http::status::request_header_fields_too_large
                        : ec == http::error::body_limit ? http::status::payload_too_large
                                                        : http::status::bad_request;
    body_left_unread_ = ec == http::error::body_limit;
    respond(http::response<http::string_body>{status, 11}, "", false);
  }

  void answer(const http::request<http::string_body>& request) {
    http::response<http::string_body> response{http::status::ok, request.version()};
    const bool keep_alive = request.keep_alive();
    const auto method = request.method();
    if (method != http::verb::get && method != http::verb::head && method != http::verb::put && method != http::verb::post) {
      response.result(http::status::method_not_allowed);
      response.set(http::field::allow, "GET, HEAD");
      return respond(std::move(response), "read only: GET or HEAD\n", keep_alive);
    }
    if (!server_.gate_) return serve(request, std::nullopt, {});
    // The request stays in parser_ while the gate decides: nothing is read until it has.
    const auto authorization = request[http::field::authorization];
    leave_gate_ = server_.gate_(std::string_view(authorization.data(), authorization.size()), peer_,
                                [this, self = this->shared_from_this()](std::optional<HttpResponse> refusal, std::string user) {
                                  leave_gate_ = nullptr;
                                  // Closed meanwhile (the server stopped): nothing to answer, and
                                  // server_ may be gone.
                                  if (closed_) return;
                                  boost::system::error_code ec;
                                  socket_().cancel(ec);  // the watch for the client's leaving
                                  serve(parser_->get(), std::move(refusal), std::move(user));
                                });
    if (leave_gate_) watch_while_waiting();
  }

  // While the gate decides, or a deferred answer is awaited, nothing is read, but a client
  // that leaves is seen, and what the gate kept for it let go (issue 43, finding 7: the
  // check of a client long gone kept its host's place). Bytes that come meanwhile (a next
  // request, a TLS record) stay in the socket for the stream to read after the answer; its
  // end behind them is seen only if it came with them, else the wait ends with the
  // verdict or the answer, as it always did.
  void watch_while_waiting() {
    socket_().async_wait(tcp::socket::wait_read, [this, self = this->shared_from_this()](const boost::system::error_code& ec) {
      if (closed_ || !(leave_gate_ || awaiting_answer_) || ec == asio::error::operation_aborted) return;
      if (ec || client_left(socket_())) finish();
    });
  }

  void serve(const http::request<http::string_body>& request, std::optional<HttpResponse> result, std::string user) {
    http::response<http::string_body> response{http::status::ok, request.version()};
    const bool keep_alive = request.keep_alive();
    if (!result) {
      const auto method = request.method_string();
      const auto target = request.target();
      constexpr bool tls = std::is_same_v<Stream, TlsStream>;
      const auto header = [&](auto field) {
        const auto value = request[field];
        return std::string_view(value.data(), value.size());
      };
      const bool another_site = web::from_another_site({.sec_fetch_site = header("Sec-Fetch-Site"),
                                                        .origin = header(http::field::origin),
                                                        .host = header(http::field::host),
                                                        .tls = tls});
      result = server_.handler_(HttpRequest{std::string_view(method.data(), method.size()),
                                            std::string_view(target.data(), target.size()), request.body(), std::move(user),
                                            peer_, tls, another_site});
    }
    if (result->later) return await_answer(std::move(result->later));
    if (result->stream && result->status == 200) return open_stream(std::move(result->stream), request.method() == http::verb::head);
    response.result(result->status);
    response.set(http::field::content_type, result->content_type);
    for (const auto& [name, value] : result->headers) response.set(name, value);
    if (request.method() == http::verb::head) {
      response.content_length(result->body.size());
      return respond(std::move(response), std::nullopt, keep_alive);
    }
    respond(std::move(response), std::move(result->body), keep_alive);
  }

  // The answer comes when the task ends (a config's probe: up to minutes), so no deadline
  // runs meanwhile; the request stays in parser_. A reply after the connection closed (its
  // client went, the server stopped) finds closed_ and touches nothing else: the server
  // may be gone.
  void await_answer(std::function<void(HttpReply)> later) {
    beast::get_lowest_layer(stream_).expires_never();
    awaiting_answer_ = true;
    later([this, self = this->shared_from_this()](HttpResponse answer) {
      if (closed_ || !std::exchange(awaiting_answer_, false)) return;
      boost::system::error_code ec;
      socket_().cancel(ec);  // the watch for the client's leaving
      serve(parser_->get(), std::move(answer), {});
    });
    if (awaiting_answer_) watch_while_waiting();
  }

  void respond(http::response<http::string_body> response, std::optional<std::string> body, bool keep_alive) {
    response.set(http::field::server, "unima-bridge");
    response.set(http::field::cache_control, "no-store");
    response.keep_alive(keep_alive);
    if (body) {
      response.body() = std::move(*body);
      response.prepare_payload();
    }
    response_ = std::make_shared<http::response<http::string_body>>(std::move(response));
    // The deadline again: the request's may have run while the gate decided.
    beast::get_lowest_layer(stream_).expires_after(server_.options_.request_timeout);
    http::async_write(stream_, *response_, [this, self = this->shared_from_this(), keep_alive](const boost::system::error_code& ec, std::size_t) {
      if (closed_) return;
      if (ec) return finish();
      request_in_progress_ = false;
      last_activity_ = Clock::now();
      if (!keep_alive) return say_goodbye();
      read();
    });
  }

  // The header, then events as they come until the client goes: no more requests on this
  // connection, and no request deadline (the browser sends nothing while it listens).
  void open_stream(std::function<void(std::shared_ptr<web::EventSink>)> start, bool head_only) {
    auto header = std::make_shared<http::response<http::empty_body>>(http::status::ok, 11);
    header->set(http::field::server, "unima-bridge");
    header->set(http::field::content_type, "text/event-stream");
    header->set(http::field::cache_control, "no-store");
    header->keep_alive(false);  // the body ends when the connection does
    beast::get_lowest_layer(stream_).expires_never();
    auto serializer = std::make_shared<http::response_serializer<http::empty_body>>(*header);
    http::async_write_header(stream_, *serializer,
                             [this, self = this->shared_from_this(), header, serializer, head_only](const boost::system::error_code& ec, std::size_t) {
                               if (closed_) return;
                               if (ec || head_only) return finish();
                               request_in_progress_ = false;  // the stream's events come unasked
                               streaming_ = true;
                               last_activity_ = Clock::now();
                               if (!queued_.empty() && !writing_) write_queued();
                               watch_for_close();
                             });
    if (!head_only) start(std::static_pointer_cast<web::EventSink>(this->shared_from_this()));
  }

  void write_queued() {
    writing_ = true;
    in_flight_.swap(queued_);
    queued_.clear();
    asio::async_write(stream_, asio::buffer(in_flight_),
                      [this, self = this->shared_from_this()](const boost::system::error_code& ec, std::size_t) {
                        writing_ = false;
                        if (closed_) return;
                        if (ec) return finish();
                        last_activity_ = Clock::now();
                        if (!queued_.empty()) write_queued();
                      });
  }

  // What a listening browser sends is nothing; its end (or garbage) closes the stream.
  void watch_for_close() {
    stream_.async_read_some(asio::buffer(discard_), [this, self = this->shared_from_this()](const boost::system::error_code& ec, std::size_t) {
      if (closed_) return;
      if (ec) return finish();
      watch_for_close();
    });
  }

  void finish() {
    if (!closed_) close();
    server_.forget(this);
  }

  // The server's own clean close (an answer that ends the connection): over TLS its
  // close_notify first, so the client knows the answer was not cut short. OpenSSL's
  // shutdown then waits for the client's close_notify, at most a second; whatever comes
  // (its alert, its TCP close, the deadline), the connection closes.
  void say_goodbye() {
    if (std::exchange(body_left_unread_, false)) return linger();
    if constexpr (std::is_same_v<Stream, TlsStream>) {
      if (handshaken_) {
        beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(1));
        return stream_.async_shutdown([this, self = this->shared_from_this()](const boost::system::error_code&) {
          if (!closed_) finish();
        });
      }
    }
    finish();
  }

  // A body refused unread (413) may still be on its way: closing with it unread makes the
  // kernel reset the connection, and the client can lose the answer before it reads it (curl
  // then says "Connection reset by peer", not 413). So what still comes is read and dropped,
  // at most max_lingering_bytes for at most max_lingering_time — until the client, having
  // sent it and read the answer, closes — and then the connection closes as any other.
  void linger() {
    beast::get_lowest_layer(stream_).expires_after(max_lingering_time);
    dropped_ = std::make_unique<std::array<char, 16 * 1024>>();
    drop_what_comes(max_lingering_bytes);
  }
  void drop_what_comes(std::size_t left) {
    stream_.async_read_some(asio::buffer(*dropped_),
                            [this, self = this->shared_from_this(), left](const boost::system::error_code& ec, std::size_t n) {
                              if (closed_) return;
                              if (ec || n >= left) {
                                dropped_.reset();
                                return say_goodbye();
                              }
                              drop_what_comes(left - n);
                            });
  }

  HttpServer& server_;
  HttpGateLeave leave_gate_;  // while the gate has this request's `done`
  Stream stream_;
  beast::flat_buffer buffer_{max_header_bytes + 1024};
  std::optional<http::request_parser<http::string_body>> parser_;
  std::shared_ptr<http::response<http::string_body>> response_;
  bool closed_ = false;
  bool handshaken_ = false;
  bool body_left_unread_ = false;                          // refused by its size: linger()
  std::unique_ptr<std::array<char, 16 * 1024>> dropped_;  // what linger() reads
  bool streaming_ = false;  // the event stream's header went out
  bool awaiting_answer_ = false;  // a deferred answer (HttpResponse::later) has not come yet
  bool writing_ = false;
  std::string queued_;
  std::string in_flight_;
  std::array<char, 512> discard_{};
};

HttpServer::HttpServer(asio::io_context& io, const HttpOptions& options, HttpHandler handler)
    : options_(options), handler_(std::move(handler)), acceptor_(io),
      accepting_(acceptor_, "http", [this](tcp::socket socket) { adopt(std::move(socket)); }) {
  const tcp::endpoint endpoint(asio::ip::make_address(options_.listen), options_.port);
  acceptor_.open(endpoint.protocol());
  acceptor_.set_option(tcp::acceptor::reuse_address(true));
  acceptor_.bind(endpoint);
  acceptor_.listen(asio::socket_base::max_listen_connections);
}

HttpServer::~HttpServer() { stop(); }

std::uint16_t HttpServer::port() const {
  boost::system::error_code ec;
  return acceptor_.local_endpoint(ec).port();
}

void HttpServer::start() {
  spdlog::info("http: serving /, /metrics, /healthz, /api/status, /api/registers, /api/events, /api/config on {}://{}:{}",
               options_.tls ? "https" : "http", options_.listen, port());
  accepting_.start();
}

void HttpServer::stop() {
  if (stopped_) return;
  stopped_ = true;
  accepting_.stop();
  boost::system::error_code ec;
  acceptor_.close(ec);
  for (const auto& c : connections_.take_all()) c->close();
}

void HttpServer::adopt(tcp::socket socket) {
  boost::system::error_code ec;
  const auto remote = socket.remote_endpoint(ec);
  if (ec) return;  // gone already
  const auto peer = remote.address().to_string() + ":" + std::to_string(remote.port());
  std::shared_ptr<ConnectionBase> evicted;
  if (connections_.size() >= options_.max_clients && !(evicted = connection_to_evict())) {
    platform::warn_from_peer("http: new clients turned away", peer,
                             "http: {} connections is the limit and each has a request in progress: {} turned away",
                             options_.max_clients, peer);
    socket.close(ec);
    return;
  }
  // Before the eviction: a refused handshake must not cost another client its connection.
  tls::HandshakeSlot handshake;
  if (options_.tls && options_.handshakes) {
    auto admitted = admit_handshake(options_.handshakes, remote.address(), peer, "https");
    if (!admitted) {
      socket.close(ec);
      return;
    }
    handshake = std::move(*admitted);
  }
  if (evicted) {
    platform::warn_from_peer("http: connections closed for a new client", evicted->peer(),
                             "http: {} connections is the limit: closing {}, idle the longest of its host's, which holds "
                             "the most, for a new client",
                             options_.max_clients, evicted->peer());
    evicted->close();
    connections_.forget(evicted.get());
  }
  std::shared_ptr<ConnectionBase> connection;
  if (options_.tls)
    connection = std::make_shared<Connection<TlsStream>>(*this, std::move(socket), *options_.tls);
  else
    connection = std::make_shared<Connection<PlainStream>>(*this, std::move(socket));
  connection->hold(std::move(handshake));
  connections_.add(connection);
  connection->start();
}

std::shared_ptr<HttpServer::ConnectionBase> HttpServer::connection_to_evict() const {
  const auto open = connections_.copy();
  std::vector<web::OpenConnection> seen;
  seen.reserve(open.size());
  for (const auto& connection : open)
    seen.push_back({platform::peer_host(connection->peer()), connection->last_activity(), connection->request_in_progress()});
  const auto chosen = web::connection_to_evict(seen);
  return chosen ? open[*chosen] : nullptr;
}

void HttpServer::forget(ConnectionBase* connection) { connections_.forget(connection); }

}  // namespace unima::io
