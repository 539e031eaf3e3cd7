#include "io/http_server.hpp"

#include <algorithm>
#include <optional>

#include <spdlog/spdlog.h>

#include "platform/beast.hpp"
#include "platform/peer_warnings.hpp"

namespace unima::io {

namespace http = beast::http;
using asio::ip::tcp;
using Clock = std::chrono::steady_clock;

namespace {

constexpr std::uint32_t max_header_bytes = 8 * 1024;

}  // namespace

class HttpServer::Connection : public std::enable_shared_from_this<Connection> {
 public:
  Connection(HttpServer& server, tcp::socket socket) : server_(server), stream_(std::move(socket)) {
    boost::system::error_code ec;
    const auto remote = stream_.socket().remote_endpoint(ec);
    peer_ = ec ? std::string("?") : remote.address().to_string() + ":" + std::to_string(remote.port());
  }

  void start() { read(); }
  void close() {
    closed_ = true;
    boost::system::error_code ec;
    stream_.socket().shutdown(tcp::socket::shutdown_both, ec);
    stream_.socket().close(ec);
  }
  Clock::time_point last_activity() const { return last_activity_; }
  const std::string& peer() const { return peer_; }

 private:
  void read() {
    parser_.emplace();
    parser_->header_limit(max_header_bytes);
    parser_->body_limit(0);  // GET and HEAD carry none
    stream_.expires_after(server_.options_.request_timeout);
    http::async_read(stream_, buffer_, *parser_,
                     [this, self = shared_from_this()](const boost::system::error_code& ec, std::size_t) {
                       if (closed_) return;
                       if (ec == http::error::end_of_stream || ec == asio::error::eof) return finish();
                       if (ec == beast::error::timeout) return finish();
                       if (ec) return refuse(ec);
                       last_activity_ = Clock::now();
                       answer(parser_->get());
                     });
  }

  // A request the parser refused (headers over 8 KiB, a body, garbage) gets 400 or 431,
  // once, and the connection closes: the stream cannot be trusted after it.
  void refuse(const boost::system::error_code& ec) {
    platform::warn_from_peer("http: bad requests", peer_, "http: {} sent a bad request: {}", peer_, ec.message());
    const bool too_large = ec == http::error::header_limit;
    respond(http::response<http::string_body>{too_large ? http::status::request_header_fields_too_large
                                                        : http::status::bad_request,
                                              11},
            "", false);
  }

  void answer(const http::request<http::string_body>& request) {
    http::response<http::string_body> response{http::status::ok, request.version()};
    const bool keep_alive = request.keep_alive();
    if (request.method() != http::verb::get && request.method() != http::verb::head) {
      response.result(http::status::method_not_allowed);
      response.set(http::field::allow, "GET, HEAD");
      return respond(std::move(response), "read only: GET or HEAD\n", keep_alive);
    }
    auto result = server_.handler_(std::string_view(request.target().data(), request.target().size()));
    response.result(result.status);
    response.set(http::field::content_type, result.content_type);
    if (request.method() == http::verb::head) {
      response.content_length(result.body.size());
      return respond(std::move(response), std::nullopt, keep_alive);
    }
    respond(std::move(response), std::move(result.body), keep_alive);
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
    http::async_write(stream_, *response_, [this, self = shared_from_this(), keep_alive](const boost::system::error_code& ec, std::size_t) {
      if (closed_) return;
      if (ec || !keep_alive) return finish();
      read();
    });
  }

  void finish() {
    if (!closed_) close();
    server_.forget(this);
  }

  HttpServer& server_;
  beast::tcp_stream stream_;
  beast::flat_buffer buffer_{max_header_bytes + 1024};
  std::optional<http::request_parser<http::string_body>> parser_;
  std::shared_ptr<http::response<http::string_body>> response_;
  std::string peer_;
  Clock::time_point last_activity_ = Clock::now();
  bool closed_ = false;
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
  spdlog::info("http: serving /metrics, /healthz, /api/status, /api/registers on {}:{}", options_.listen, port());
  accepting_.start();
}

void HttpServer::stop() {
  if (stopped_) return;
  stopped_ = true;
  accepting_.stop();
  boost::system::error_code ec;
  acceptor_.close(ec);
  auto connections = std::move(connections_);
  for (const auto& c : connections) c->close();
}

void HttpServer::adopt(tcp::socket socket) {
  if (connections_.size() >= options_.max_clients) {
    const auto idlest = *std::min_element(connections_.begin(), connections_.end(), [](const auto& a, const auto& b) {
      return a->last_activity() < b->last_activity();
    });
    platform::warn_from_peer("http: connections closed for a new client", idlest->peer(),
                             "http: {} connections is the limit: closing {}, the longest idle, for a new client",
                             options_.max_clients, idlest->peer());
    idlest->close();
    connections_.erase(idlest);
  }
  auto connection = std::make_shared<Connection>(*this, std::move(socket));
  connections_.insert(connection);
  connection->start();
}

void HttpServer::forget(Connection* connection) {
  for (auto it = connections_.begin(); it != connections_.end(); ++it)
    if (it->get() == connection) {
      connections_.erase(it);
      return;
    }
}

}  // namespace unima::io
