#pragma once
// What each path of the HTTP server answers (SPEC §13): the page's files, /healthz,
// /metrics and /api/status from the status document (so they never disagree with
// `unima-bridge status`), /api/registers with each register's raw value and the value
// model's values, /api/events the page's live feed.

#include <string_view>

#include "io/http/http_server.hpp"
#include "io/http/loop_health.hpp"
#include "io/runtime.hpp"
#include "web/live_view.hpp"

namespace unima::io {

class HttpAnswers {
 public:
  HttpAnswers(Runtime& runtime, web::LiveView& live, const LoopHealth& health)
      : runtime_(runtime), live_(live), health_(health) {}

  HttpResponse answer(std::string_view target);
  /// What the front page shows now.
  web::LiveSnapshot live_snapshot() const;
  /// The same without the panel (which costs the status document): the registers and values.
  web::LiveSnapshot live_values() const;

 private:
  HttpResponse registers() const;

  Runtime& runtime_;
  web::LiveView& live_;
  const LoopHealth& health_;
};

}  // namespace unima::io
