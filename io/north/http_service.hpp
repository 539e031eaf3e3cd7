#pragma once
// HTTP (`http`, SPEC §13) as a service: the server (plain or TLS), who may ask
// (`http.users`), the loop's heartbeat that /healthz reports and that feeds the front
// pages listening to /api/events. A reload keeps the listener when its address, port and
// TLS did not change (renewed certificates and users apply at once); a users file that
// can no longer be read keeps the users read before.

#include <memory>
#include <optional>

#include "io/north/http_answers.hpp"
#include "io/north/http_server.hpp"
#include "io/movable_listener.hpp"
#include "io/service.hpp"
#include "web/basic_auth.hpp"
#include "web/live_view.hpp"

namespace unima::io {

class HttpService final : public Service {
 public:
  explicit HttpService(Runtime& runtime);

  void start() override;
  void stop() override;
  void stage(const Banks& next) override;
  void abandon() override;
  void commit(const Banks& previous) override;

 private:
  std::unique_ptr<HttpServer> make_server(const config::Config& config);
  std::unique_ptr<HttpServer> serve(const HttpOptions& options);
  /// `config`'s users; nullopt when it has none. Throws when they cannot be read, unless
  /// the running config named the same file: then the users read before stay, logged.
  std::optional<web::BasicAuth> read_users(const config::Config& config) const;
  std::optional<HttpResponse> gate(std::string_view authorization, const std::string& peer);
  void heartbeat();

  Runtime& runtime_;
  web::LiveView live_;  // the front pages listening to /api/events
  LoopHealth health_;
  HttpAnswers answers_{runtime_, live_, health_};
  std::optional<web::BasicAuth> users_;  // nullopt: the server asks no one
  MovableListener<HttpServer> server_{nullptr};
  asio::steady_timer heartbeat_timer_;
  bool started_ = false;
  // Staged by a reload:
  std::shared_ptr<asio::ssl::context> next_tls_;  // same endpoint: http.tls read again
  std::optional<web::BasicAuth> next_users_;
};

}  // namespace unima::io
