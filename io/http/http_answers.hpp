#pragma once
// What each path of the HTTP server answers (SPEC §13): the page's files, /healthz,
// /metrics and /api/status from the status document (so they never disagree with
// `unima-bridge status`), /api/registers with each register's raw value and the value
// model's values, /api/events the page's live feed; /api/config is HttpConfigAnswers'.

#include <map>
#include <memory>
#include <string_view>

#include "io/http/config_answers.hpp"
#include "io/http/http_server.hpp"
#include "io/http/loop_health.hpp"
#include "io/runtime.hpp"
#include "web/live_view.hpp"

namespace unima::io {

class HttpAnswers {
 public:
  HttpAnswers(Runtime& runtime, web::LiveView& live, const LoopHealth& health)
      : runtime_(runtime), live_(live), health_(health) {}

  HttpResponse answer(const HttpRequest& request);
  /// What the front page shows now.
  web::LiveSnapshot live_snapshot() const;
  /// The same without the panel (which costs the status document): the registers and values.
  web::LiveSnapshot live_values() const;
  /// The running banks were replaced (a reload): no bank's page values are reused.
  void forget_values() { named_banks_.clear(); }

 private:
  HttpResponse registers() const;
  /// `bank`'s values as the page shows them, rendered again only when the bank changed.
  std::shared_ptr<const web::NamedValues> named_values(const values::BankValues& layout) const;

  Runtime& runtime_;
  web::LiveView& live_;
  const LoopHealth& health_;
  HttpConfigAnswers config_{runtime_};
  struct RenderedBank {
    std::uint64_t at = 0;  // the store's changes() of the bank when rendered
    std::shared_ptr<const web::NamedValues> values;
  };
  mutable std::map<banks::BankId, RenderedBank> named_banks_;  // the running banks' only (forget_values)
};

}  // namespace unima::io
