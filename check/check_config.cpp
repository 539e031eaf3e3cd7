#include "check/check_config.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "report/deadbands.hpp"
#include "tls/server_credentials.hpp"
#include "values/value_model.hpp"
#include "web/basic_auth.hpp"

namespace unima::check {

namespace {

// The daemon loads these at start: a file it cannot use is an error here too.
void check_tls_credentials(const config::Config& config) {
  if (const auto& tls = config.modbus.tls) {
    try {
      (void)tls::load_server_credentials({tls->certificate, tls->key, tls->ca});
    } catch (const std::exception& e) {
      throw std::runtime_error(fmt::format("{}: {}", tls->origin, e.what()));
    }
  }
  if (const auto& http = config.http; http && http->tls) {
    try {
      (void)tls::load_server_credentials({http->tls->certificate, http->tls->key, {}}, "http.tls");
    } catch (const std::exception& e) {
      throw std::runtime_error(fmt::format("{}: {}", http->origin, e.what()));
    }
  }
}

// The users file as the daemon reads it; every user remote_config.http lets PUT a config
// must be in it, or that user could never authenticate (a name mistyped locks nobody out,
// but nobody in either).
void check_http_users(const config::Config& config) {
  const auto& http = config.http;
  if (!http || http->users.empty()) return;
  const auto users = web::BasicAuth::load(http->users, http->users_origin);
  if (!config.remote_config) return;
  for (const auto& user : config.remote_config->http) {
    if (!users.has_user(user))
      throw config::ConfigError(fmt::format("{}: remote_config.http: '{}' is not a user of http.users ({}): add the "
                                            "user to that file, or take the name out of the list",
                                            config.remote_config->http_origin, user, http->users));
  }
}

}  // namespace

void check_config(const config::Config& config) {
  (void)config::address_map(config);
  // The daemon checks these at start: a deadband that names no value is an error here too.
  (void)report::Deadbands(config.report, values::ValueModel(config));
  check_tls_credentials(config);
  check_http_users(config);
}

}  // namespace unima::check
