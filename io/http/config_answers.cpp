#include "io/http/config_answers.hpp"

#include <algorithm>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "config/endpoint.hpp"
#include "platform/peer_warnings.hpp"

namespace unima::io {

namespace {

constexpr auto config_json_type = "application/json";

HttpResponse config_error(unsigned status, const std::string& message) {
  return {status, config_json_type, nlohmann::json{{"error", message}}.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n",
          {}, {}, {}};
}

HttpResponse config_method_not_allowed(std::string allowed) {
  return {405, plain_text_type, "allowed here: " + allowed + "\n", {{"Allow", allowed}}, {}, {}};
}

// "127.0.0.1:5000", "::1:5000", "::ffff:127.0.0.1:5000": the peer is this machine.
bool from_loopback(const std::string& peer) { return config::is_loopback_address(platform::peer_host(peer)); }

HttpResponse change_response(const remote::ChangeAnswer& answer) {
  return {http_status_of(answer.result), config_json_type, remote::answer_json(answer) + "\n", {}, {}, {}};
}

}  // namespace

unsigned http_status_of(remote::Result result) {
  switch (result) {
    case remote::Result::applied: return 200;
    case remote::Result::busy: return 409;
    case remote::Result::refused: return 422;
    case remote::Result::rolled_back: return 502;
  }
  return 500;
}

HttpResponse HttpConfigAnswers::answer(const HttpRequest& request, std::string_view request_path) const {
  const bool revert = request_path == revert_path;
  if (!revert && (request.method == "GET" || request.method == "HEAD")) return show(request);
  if (!revert && request.method != "PUT") return config_method_not_allowed("GET, HEAD, PUT");
  if (revert && request.method != "POST") return config_method_not_allowed("POST");
  const auto what = fmt::format("{} {}", request.method, request_path);
  if (auto refused = refusal(request, what)) return std::move(*refused);
  auto* changes = runtime_.config_changes;
  HttpResponse response;
  if (revert) {
    response.later = [changes, by = request.user](HttpReply reply) {
      changes->revert(remote::Source::http, by, [reply](const remote::ChangeAnswer& a) { reply(change_response(a)); });
    };
  } else {
    response.later = [changes, text = std::string(request.body), by = request.user](HttpReply reply) {
      changes->apply(text, remote::Source::http, by, [reply](const remote::ChangeAnswer& a) { reply(change_response(a)); });
    };
  }
  return response;
}

std::optional<HttpResponse> HttpConfigAnswers::refusal(const HttpRequest& request, std::string_view what) const {
  if (!runtime_.config_changes) return config_error(503, "this daemon takes no config changes");
  if (!request.tls && !from_loopback(request.peer)) {
    platform::warn_from_peer("http: config changes refused", request.peer, "http: {} sent {} over plain HTTP: refused, it needs HTTPS",
                             request.peer, what);
    return config_error(403, fmt::format("{} needs HTTPS", what));
  }
  if (request.from_another_site) {
    platform::warn_from_peer("http: config changes refused", request.peer,
                             "http: {} ({}) sent {} from another site's page: refused", request.user, request.peer, what);
    return config_error(403, fmt::format("{} must come from this bridge's own page or from a client that is not a browser, "
                                         "not from another site's page",
                                         what));
  }
  if (request.user.empty())
    return config_error(403, fmt::format("{} needs a user of http.users that remote_config.http lists; this server asks no one's "
                                         "name (http.users is not set)",
                                         what));
  if (!listed(request)) {
    platform::warn_from_peer("http: config changes refused", request.peer, "http: {} ({}) may not {}: remote_config.http does not list it",
                             request.user, request.peer, what);
    return config_error(403, fmt::format("{} may not {}: remote_config.http does not list this user", request.user, what));
  }
  return std::nullopt;
}

bool HttpConfigAnswers::listed(const HttpRequest& request) const {
  const auto& remote = runtime_.config().remote_config;
  return !request.user.empty() && remote && std::find(remote->http.begin(), remote->http.end(), request.user) != remote->http.end();
}

// The text may hold passwords (a broker's, a key's path): only for who may change it, and
// as a change would come.
HttpResponse HttpConfigAnswers::show(const HttpRequest& request) const {
  const auto* changes = runtime_.config_changes;
  if (!changes) return config_error(503, "this daemon takes no config changes");
  auto shown = changes->history();
  const bool may_change = listed(request) && (request.tls || from_loopback(request.peer));
  if (may_change) {
    shown["in_force"] = changes->in_force(true);
    shown["in_force"]["replaced"] = changes->replaced();
  }
  // For the page: whether to offer this user the form, and whether the box is worth showing.
  shown["may_change"] = may_change;
  const auto& remote = runtime_.config().remote_config;
  shown["takes_changes_from_afar"] = remote && (remote->mqtt || !remote->http.empty());
  return {200, config_json_type, shown.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n", {}, {}, {}};
}

}  // namespace unima::io
