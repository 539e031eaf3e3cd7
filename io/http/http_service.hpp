#pragma once
// HTTP (`http`, SPEC §13) as a service: the server (plain or TLS), who may ask
// (`http.users`: the hashes computed by a PasswordWorker, within web::LoginLimits), the
// loop's heartbeat that /healthz reports and that feeds the front pages listening to
// /api/events their panel and monitor lines; their values go when the banks change, on
// the leading edge (values/leading_edge: at once after a quiet 100 ms). A reload keeps the listener when its address, port and
// TLS did not change (renewed certificates and users apply at once); a users file that
// can no longer be read keeps the users read before.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "io/http/http_answers.hpp"
#include "io/http/http_server.hpp"
#include "io/http/password_worker.hpp"
#include "io/movable_listener.hpp"
#include "io/service.hpp"
#include "values/leading_edge.hpp"
#include "web/basic_auth.hpp"
#include "web/live_view.hpp"
#include "web/login_limits.hpp"

namespace unima::io {

class HttpService final : public Service {
 public:
  explicit HttpService(Runtime& runtime);

  void start() override;
  void stop() override;
  void stage(const Banks& next) override;
  void abandon() override;
  void commit(const Banks& previous) override;
  void describe(status::Document& status) const override;
  void probe(remote::ProbeFacts& facts) const override;

 private:
  struct PendingCheck;
  std::unique_ptr<HttpServer> make_server(const config::Config& config);
  std::unique_ptr<HttpServer> serve(const HttpOptions& options);
  /// `config`'s users; nullopt when it has none. Throws when they cannot be read, unless
  /// the running config named the same file: then the users read before stay, logged.
  std::optional<web::BasicAuth> read_users(const config::Config& config) const;
  HttpGateLeave gate(std::string_view authorization, const std::string& peer, HttpGateDone done);
  /// `done` waits in `pending`; the connection leaves with what this returns.
  HttpGateLeave wait_for(PendingCheck& pending, const std::string& peer, HttpGateDone done);
  /// The connection of waiter `id` went: its check is abandoned, and its host's place given
  /// back, when nobody else waits for it.
  void left(std::uint64_t id);
  void checked(const std::string& authorization, bool hash_matched);
  HttpResponse unauthorized(const std::string& peer, bool gave_credentials);
  void heartbeat();
  /// The banks changed: the pages get the values now, or when their 100 ms are up.
  void values_changed();
  void send_values();

  Runtime& runtime_;
  web::LiveView live_;  // the front pages listening to /api/events
  LoopHealth health_;
  HttpAnswers answers_{runtime_, live_, health_};
  std::optional<web::BasicAuth> users_;  // nullopt: the server asks no one
  std::uint64_t users_generation_ = 0;    // counts reloads of users_
  web::LoginLimits login_limits_;
  // A check being computed, by Authorization header: a browser's parallel requests with
  // the same new header wait for the one hash.
  struct PendingCheck {
    web::PasswordCheck check;
    PasswordWorker::Ticket ticket;
    std::string host;
    std::uint64_t users_generation = 0;
    struct Waiter {
      std::uint64_t id = 0;
      std::string peer;
      HttpGateDone done;
    };
    std::vector<Waiter> waiting;
  };
  std::map<std::string, PendingCheck, std::less<>> checks_;
  std::uint64_t next_waiter_ = 0;
  struct LoginCounters {
    std::uint64_t checked = 0;        // hashes computed
    std::uint64_t wrong = 0;          // credentials given and refused (401)
    std::uint64_t peer_limited = 0;   // 429
    std::uint64_t busy = 0;           // 503
  } login_counters_;
  // HTTPS' handshakes a host may start, kept across reloads that move the port.
  std::shared_ptr<tls::HandshakeLimiter> handshakes_ = std::make_shared<tls::HandshakeLimiter>();
  MovableListener<HttpServer> server_{nullptr};
  asio::steady_timer heartbeat_timer_;
  // Of the values sent alone: the heartbeat's own update does not hold a change back.
  values::LeadingEdge values_edge_;
  asio::steady_timer values_timer_;  // a change within the 100 ms: when they are up
  bool values_timer_armed_ = false;
  bool started_ = false;
  // Staged by a reload:
  std::shared_ptr<asio::ssl::context> next_tls_;  // same endpoint: http.tls read again
  std::optional<web::BasicAuth> next_users_;
  // Last: gone first, so that no verdict comes back to what is destroyed.
  PasswordWorker passwords_{runtime_.io};
};

}  // namespace unima::io
