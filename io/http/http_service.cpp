#include "io/http/http_service.hpp"

#include <algorithm>

#include <spdlog/spdlog.h>

#include "io/handshake_admission.hpp"
#include "io/http/config_answers.hpp"
#include "io/listen_error.hpp"
#include "io/tls_context.hpp"
#include "platform/peer_warnings.hpp"
#include "web/login_status.hpp"

namespace unima::io {

namespace {


std::optional<std::tuple<std::string, std::uint16_t, bool>> endpoint(const config::Config& c) {
  if (!c.http) return std::nullopt;
  return std::tuple(c.http->listen, c.http->port, c.http->tls.has_value());
}

}  // namespace

HttpService::HttpService(Runtime& runtime) : runtime_(runtime), heartbeat_timer_(runtime.io), values_timer_(runtime.io) {
  users_ = read_users(runtime.config());
  server_ = MovableListener<HttpServer>(make_server(runtime.config()));
  runtime.changes.listen([this] {
    if (started_ && live_.listened()) values_changed();
  });
}

std::unique_ptr<HttpServer> HttpService::make_server(const config::Config& config) {
  if (!config.http) return nullptr;
  HttpOptions options;
  options.listen = config.http->listen;
  options.port = config.http->port;
  options.max_clients = config.http->max_clients;
  options.port_origin = config.http->port_origin;
  options.max_body = HttpConfigAnswers::max_body;
  if (const auto& tls = config.http->tls) {
    options.tls = make_server_tls_context(http_tls_files(*tls), "http.tls");
    options.handshakes = handshakes_;
  }
  return serve(options);
}

std::unique_ptr<HttpServer> HttpService::serve(const HttpOptions& options) {
  try {
    auto server = std::make_unique<HttpServer>(runtime_.io, options, [this](const HttpRequest& request) { return answers_.answer(request); });
    server->set_gate([this](std::string_view authorization, const std::string& peer, HttpGateDone done) {
      return gate(authorization, peer, std::move(done));
    });
    return server;
  } catch (const boost::system::system_error& e) {
    throw std::runtime_error(listen_error(options.port_origin, fmt::format("http.port {}", options.port),
                                          listen_address(options.listen, options.port), e.code()));
  }
}

std::optional<web::BasicAuth> HttpService::read_users(const config::Config& config) const {
  if (!config.http || config.http->users.empty()) return std::nullopt;
  try {
    return web::BasicAuth::load(config.http->users, config.http->users_origin);
  } catch (const std::exception& e) {
    const auto& running = runtime_.config();
    if (users_ && running.http && running.http->users == config.http->users) {
      spdlog::error("{}; the users read before stay", e.what());
      return users_;
    }
    throw;
  }
}

// Answered on the loop when no hash is needed; else the hash is computed by the worker and
// the request answered when it is back (checked()). web::LoginLimits decides who may start one.
HttpGateLeave HttpService::gate(std::string_view authorization, const std::string& peer, HttpGateDone done) {
  // Answered here and now: the connection has nothing to leave.
  const auto answer = [&done](std::optional<HttpResponse> refusal, std::string user = {}) -> HttpGateLeave {
    done(std::move(refusal), std::move(user));
    return nullptr;
  };
  if (!users_) return answer(std::nullopt);
  auto judgement = users_->judge(authorization);
  switch (judgement.verdict) {
    case web::BasicAuth::Verdict::allowed:
      return answer(std::nullopt, judgement.user);
    case web::BasicAuth::Verdict::refused:
      return answer(unauthorized(peer, !authorization.empty()));
    case web::BasicAuth::Verdict::check:
      break;
  }
  if (const auto same = checks_.find(authorization); same != checks_.end()) {
    web::forget_password(judgement.check->password);
    return wait_for(same->second, peer, std::move(done));
  }
  const std::string host(platform::peer_host(peer));
  const auto retry_after = std::to_string(web::LoginLimits::retry_after.count());
  switch (login_limits_.admit(host, web::LoginLimits::Clock::now())) {
    case web::LoginLimits::Admission::admitted:
      break;
    case web::LoginLimits::Admission::peer_limited:
      ++login_counters_.peer_limited;
      web::forget_password(judgement.check->password);
      platform::warn_from_peer("http: logins refused as too many from one host", peer,
                               "http: {} asks for more password checks than {} at once and {} a second: told to wait", peer,
                               login_limits_.options().checks_per_host, login_limits_.options().host_rate);
      return answer(HttpResponse{429, plain_text_type, "too many logins from your address: try again in a second\n",
                                 {{"Retry-After", retry_after}}, {}, {}});
    case web::LoginLimits::Admission::busy:
      ++login_counters_.busy;
      web::forget_password(judgement.check->password);
      platform::warn_from_peer("http: logins refused as too many at once", peer,
                               "http: {} password checks are waiting already: {} told to come back", login_limits_.options().checks,
                               peer);
      return answer(HttpResponse{503, plain_text_type, "too many logins at once: try again in a second\n", {{"Retry-After", retry_after}}, {}, {}});
  }
  ++login_counters_.checked;
  auto& pending = checks_[std::string(authorization)];
  pending.host = host;
  pending.users_generation = users_generation_;
  pending.check = std::move(*judgement.check);
  pending.ticket = passwords_.check(std::move(pending.check.password), pending.check.hash,
                                    [this, header = std::string(authorization)](bool hash_matched) { checked(header, hash_matched); });
  return wait_for(pending, peer, std::move(done));
}

HttpGateLeave HttpService::wait_for(PendingCheck& pending, const std::string& peer, HttpGateDone done) {
  const auto id = next_waiter_++;
  pending.waiting.push_back({id, peer, std::move(done)});
  return [this, id] { left(id); };
}

// A check nobody waits for any more is not worth its hash, nor its host's place: a client
// that left (or was closed) would keep its host from logging in again until the hash came
// back (issue 43, finding 7).
void HttpService::left(std::uint64_t id) {
  for (auto pending = checks_.begin(); pending != checks_.end(); ++pending) {
    auto& waiting = pending->second.waiting;
    const auto waiter = std::find_if(waiting.begin(), waiting.end(), [id](const auto& w) { return w.id == id; });
    if (waiter == waiting.end()) continue;
    waiting.erase(waiter);
    if (!waiting.empty()) return;
    pending->second.ticket.abandon();
    login_limits_.release(pending->second.host);
    checks_.erase(pending);
    return;
  }
}

void HttpService::checked(const std::string& authorization, bool hash_matched) {
  auto node = checks_.extract(authorization);
  if (node.empty()) return;
  auto& pending = node.mapped();
  login_limits_.release(pending.host);
  const bool passed = pending.check.passed(hash_matched);
  // A check begun before a reload answers its requests, but the users read since decide
  // whether the header is remembered: it may name a user they no longer hold.
  if (passed && users_ && pending.users_generation == users_generation_) users_->remember(pending.check);
  for (auto& waiter : pending.waiting)
    waiter.done(passed ? std::nullopt : std::optional(unauthorized(waiter.peer, true)), passed ? pending.check.user : std::string{});
}

HttpResponse HttpService::unauthorized(const std::string& peer, bool gave_credentials) {
  if (gave_credentials) {
    ++login_counters_.wrong;
    platform::warn_from_peer("http: logins refused", peer, "http: {} gave a name and password that http.users does not hold", peer);
  }
  return HttpResponse{401, plain_text_type, "log in: a name and password of http.users\n",
                      {{"WWW-Authenticate", "Basic realm=\"unima-bridge\", charset=\"UTF-8\""}}, {}, {}};
}

void HttpService::values_changed() {
  const auto now = values::LeadingEdge::Clock::now();
  const auto when = values_edge_.when(now);
  if (when <= now) return send_values();
  if (std::exchange(values_timer_armed_, true)) return;
  values_timer_.expires_at(when);
  values_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec) return;
    values_timer_armed_ = false;
    if (started_ && live_.listened()) send_values();
  });
}

void HttpService::send_values() {
  live_.update_values(answers_.live_values());
  values_edge_.went(values::LeadingEdge::Clock::now());
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
  values_timer_.cancel();
  values_timer_armed_ = false;
}

void HttpService::stage(const Banks& next) {
  next_users_ = read_users(next.config);
  if (endpoint(runtime_.config()) != endpoint(next.config)) return server_.move([&] { return make_server(next.config); });
  // As for Modbus/TCP Security: renewed files are read, bad ones leave the running ones.
  if (server_ && next.config.http->tls) {
    try {
      const auto& tls = *next.config.http->tls;
      next_tls_ = make_server_tls_context(http_tls_files(tls), "http.tls");
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
  answers_.forget_values();
  users_ = std::move(next_users_);
  ++users_generation_;
  next_users_.reset();
  server_.commit();
  if (server_ && next_tls_) server_->set_tls_context(std::move(next_tls_));
  next_tls_.reset();
}

void HttpService::probe(remote::ProbeFacts& facts) const {
  const auto& http = runtime_.config().http;
  if (!http) return;
  facts.listeners.emplace_back(fmt::format("http {}:{}", http->listen, http->port), static_cast<bool>(server_));
  facts.http = static_cast<bool>(server_);
}

void HttpService::describe(status::Document& status) const {
  if (server_ && server_->tls()) status.http.handshakes = handshake_counters(*handshakes_);
  if (!users_) return;
  const auto& c = login_counters_;
  status.http.logins = web::LoginStatus{c.checked, c.wrong, c.peer_limited, c.busy, login_limits_.in_flight()};
}

}  // namespace unima::io
