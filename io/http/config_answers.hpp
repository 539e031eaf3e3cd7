#pragma once
// HTTP's channel of the one flow of configs from afar (SPEC §19): PUT /api/config (the text
// of a whole config), POST /api/config/revert (back to the operator's file) and GET
// /api/config (the config in force and the history). A change comes only from a user of
// http.users whom the running config's remote_config.http lists, and over HTTPS unless
// from this machine: the password, and a config that may hold more, are not sent in the
// clear. Its answer (remote::answer_json) comes when the flow ends — after the probe, up
// to minutes — so the connection waits for it (HttpResponse::later).

#include <cstddef>
#include <optional>
#include <string_view>

#include "io/http/http_server.hpp"
#include "io/runtime.hpp"
#include "remote/change_answer.hpp"
#include "remote/yaml_budget.hpp"

namespace unima::io {

/// A change's answer as HTTP's status: 200 applied, 409 busy, 422 refused (nothing
/// changed), 502 rolled back (the bridge runs, but what the config named — a broker, a
/// listener — did not work within the probe).
unsigned http_status_of(remote::Result result);

class HttpConfigAnswers {
 public:
  static constexpr std::string_view path = "/api/config";
  static constexpr std::string_view revert_path = "/api/config/revert";
  /// The body PUT may send: the largest config the flow reads, and a margin so that one a
  /// little over is answered by the flow (422, with the reason) rather than cut (413).
  static constexpr std::size_t max_body = remote::YamlBudget{}.max_bytes + 16 * 1024;

  explicit HttpConfigAnswers(Runtime& runtime) : runtime_(runtime) {}

  /// The answer to `request` of `path` or `revert_path` (its path, without a query).
  HttpResponse answer(const HttpRequest& request, std::string_view request_path) const;

 private:
  HttpResponse show(const HttpRequest& request) const;
  /// Why `request` may not change the config (403, 503); nullopt when it may.
  std::optional<HttpResponse> refusal(const HttpRequest& request, std::string_view what) const;
  /// The running config's remote_config.http lists the request's user.
  bool listed(const HttpRequest& request) const;

  Runtime& runtime_;
};

}  // namespace unima::io
