#include "io/north/http_service.hpp"

#include <spdlog/spdlog.h>

#include "io/tls_context.hpp"
#include "platform/peer_warnings.hpp"

namespace unima::io {

namespace {

constexpr auto text_type = "text/plain; charset=utf-8";

std::optional<std::tuple<std::string, std::uint16_t, bool>> endpoint(const config::Config& c) {
  if (!c.http) return std::nullopt;
  return std::tuple(c.http->listen, c.http->port, c.http->tls.has_value());
}

}  // namespace

HttpService::HttpService(Runtime& runtime) : runtime_(runtime), heartbeat_timer_(runtime.io) {
  users_ = read_users(runtime.config());
  server_ = MovableListener<HttpServer>(make_server(runtime.config()));
}

std::unique_ptr<HttpServer> HttpService::make_server(const config::Config& config) {
  if (!config.http) return nullptr;
  HttpOptions options;
  options.listen = config.http->listen;
  options.port = config.http->port;
  options.max_clients = config.http->max_clients;
  if (const auto& tls = config.http->tls) options.tls = make_server_tls_context({tls->certificate, tls->key, {}}, "http.tls");
  return serve(options);
}

std::unique_ptr<HttpServer> HttpService::serve(const HttpOptions& options) {
  try {
    auto server = std::make_unique<HttpServer>(runtime_.io, options, [this](std::string_view target) { return answers_.answer(target); });
    server->set_gate([this](std::string_view authorization, const std::string& peer) { return gate(authorization, peer); });
    return server;
  } catch (const boost::system::system_error& e) {
    throw std::runtime_error(fmt::format("http: cannot listen on {}:{}: {}", options.listen, options.port, e.code().message()));
  }
}

std::optional<web::BasicAuth> HttpService::read_users(const config::Config& config) const {
  if (!config.http || config.http->users.empty()) return std::nullopt;
  try {
    return web::BasicAuth::load(config.http->users);
  } catch (const std::exception& e) {
    const auto& running = runtime_.config();
    if (users_ && running.http && running.http->users == config.http->users) {
      spdlog::error("{}; the users read before stay", e.what());
      return users_;
    }
    throw;
  }
}

std::optional<HttpResponse> HttpService::gate(std::string_view authorization, const std::string& peer) {
  if (!users_) return std::nullopt;
  const auto result = users_->check(authorization, web::BasicAuth::Clock::now());
  switch (result.verdict) {
    case web::BasicAuth::Verdict::allowed:
      return std::nullopt;
    case web::BasicAuth::Verdict::too_many:
      platform::warn_from_peer("http: logins refused as too many", peer,
                               "http: too many logins to check ({} a second): {} asked to wait", web::BasicAuth::checks_per_second, peer);
      return HttpResponse{429, text_type, "too many logins at once: try again in a second\n", {{"Retry-After", "1"}}, {}};
    case web::BasicAuth::Verdict::refused:
      break;
  }
  if (!authorization.empty())
    platform::warn_from_peer("http: logins refused", peer, "http: {} gave a name and password that http.users does not hold", peer);
  return HttpResponse{401, text_type, "log in: a name and password of http.users\n",
                      {{"WWW-Authenticate", "Basic realm=\"unima-bridge\", charset=\"UTF-8\""}}, {}};
}

void HttpService::heartbeat() {
  health_.beat(LoopHealth::Clock::now());
  if (live_.listened()) live_.update(answers_.live_snapshot(), runtime_.monitor->recent());
  heartbeat_timer_.expires_after(LoopHealth::beat_interval);
  heartbeat_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec && started_) heartbeat();
  });
}

void HttpService::start() {
  started_ = true;
  server_.start();
  heartbeat();
}

void HttpService::stop() {
  started_ = false;
  server_.stop();
  heartbeat_timer_.cancel();
}

void HttpService::stage(const Banks& next) {
  next_users_ = read_users(next.config);
  if (endpoint(runtime_.config()) != endpoint(next.config)) return server_.move([&] { return make_server(next.config); });
  // As for Modbus/TCP Security: renewed files are read, bad ones leave the running ones.
  if (server_ && next.config.http->tls) {
    try {
      const auto& tls = *next.config.http->tls;
      next_tls_ = make_server_tls_context({tls.certificate, tls.key, {}}, "http.tls");
    } catch (const std::exception& e) {
      spdlog::error("http: {}; the running certificate keeps serving", e.what());
    }
  }
}

void HttpService::abandon() {
  next_tls_.reset();
  next_users_.reset();
  server_.abandon([this](const HttpOptions& options) { return serve(options); });
}

void HttpService::commit(const Banks&) {
  users_ = std::move(next_users_);
  next_users_.reset();
  server_.commit();
  if (server_ && next_tls_) server_->set_tls_context(std::move(next_tls_));
  next_tls_.reset();
}

}  // namespace unima::io
