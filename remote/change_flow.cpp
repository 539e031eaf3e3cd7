#include "remote/change_flow.hpp"

#include <fmt/format.h>

namespace unima::remote {

std::string probe_shortfall(const ProbeFacts& facts) {
  std::vector<std::string> missing;
  for (const auto& [listener, bound] : facts.listeners)
    if (!bound) missing.push_back(listener + " not bound");
  if (facts.broker == false) missing.push_back("the MQTT broker has not accepted the bridge");
  if (facts.http == false) missing.push_back("the HTTP server does not answer");
  std::string text;
  for (const auto& m : missing) text += (text.empty() ? "" : "; ") + m;
  return text;
}

std::optional<ChangeAnswer> ChangeFlow::begin(Change change) {
  if (current_) {
    const auto reason = fmt::format("another change ({} by {}) is {}", source_name(current_->source), current_->by,
                                    deadline_ ? "being probed" : "being applied");
    return ChangeAnswer{std::move(change.id), Result::busy, {}, reason, change.source, std::move(change.by)};
  }
  current_ = std::move(change);
  return std::nullopt;
}

ChangeAnswer ChangeFlow::answer(Result result, std::string reason, std::vector<ErrorAt> errors) {
  ChangeAnswer a{current_->id, result, std::move(errors), std::move(reason), current_->source, current_->by};
  current_.reset();
  deadline_.reset();
  return a;
}

ChangeAnswer ChangeFlow::refuse(std::string reason, std::vector<ErrorAt> errors) {
  return answer(Result::refused, std::move(reason), std::move(errors));
}

void ChangeFlow::committed(Clock::time_point now, Clock::duration probe) { deadline_ = now + probe; }

std::optional<ChangeAnswer> ChangeFlow::probe(const ProbeFacts& facts, Clock::time_point now) {
  if (!current_ || !deadline_) return std::nullopt;
  auto shortfall = probe_shortfall(facts);
  if (shortfall.empty()) return answer(Result::applied, {});
  if (now < *deadline_) return std::nullopt;
  return answer(Result::rolled_back, "the new config did not prove itself in time: " + shortfall);
}

}  // namespace unima::remote
