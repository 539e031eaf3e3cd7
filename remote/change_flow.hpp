#pragma once
// The one flow every config from afar goes through (SPEC §19), whichever channel it came
// by: one change at a time; refused with the reason before anything changed (the check's
// errors, a stage that failed, a rule of admission); else committed as a reload and probed.
// Only once the probe has seen everything the new config names working is the change
// `applied`; a probe that has not by its deadline takes the bridge back to the config
// before — `rolled_back`, with what was missing. Pure: io's coordinator does the reloads
// and gathers the probe's facts, and asks this at each step.

#include <chrono>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "remote/change_answer.hpp"

namespace unima::remote {

/// What the probe looks at, gathered from the running services.
struct ProbeFacts {
  std::vector<std::pair<std::string, bool>> listeners;  // each listener the config names ("modbus.tcp 0.0.0.0:502"), bound
  std::optional<bool> broker;  // the MQTT broker the config names has accepted the bridge; nullopt: none named
  std::optional<bool> http;    // the HTTP server answers; nullopt: none configured
};

/// What is not working yet ("modbus.tcp 0.0.0.0:502 not bound; the MQTT broker has not
/// accepted the bridge"); empty when everything is.
std::string probe_shortfall(const ProbeFacts& facts);

class ChangeFlow {
 public:
  using Clock = std::chrono::steady_clock;
  struct Change {
    std::string id;  // change_id of its text
    Source source = Source::cli;
    std::string by;
  };

  bool busy() const { return current_.has_value(); }
  /// A change arrives: nullopt when the flow is now this change's, else the answer `busy`
  /// (the change under way is not touched).
  std::optional<ChangeAnswer> begin(Change change);
  /// The change is refused before anything changed: its answer; the flow is free again.
  ChangeAnswer refuse(std::string reason, std::vector<ErrorAt> errors = {});
  /// The change was committed at `now`: it proves itself until now + `probe`.
  void committed(Clock::time_point now, Clock::duration probe);
  bool probing() const { return deadline_.has_value(); }
  /// When the probe must have passed; only while probing.
  Clock::time_point deadline() const { return *deadline_; }
  /// The probe looks at `facts` at `now`: `applied` once everything works, `rolled_back`
  /// with what did not when the deadline has come (the coordinator has gone back to the
  /// previous config before it sends this), nullopt while the probe goes on. The flow is
  /// free again once it answers.
  std::optional<ChangeAnswer> probe(const ProbeFacts& facts, Clock::time_point now);

 private:
  ChangeAnswer answer(Result result, std::string reason, std::vector<ErrorAt> errors = {});

  std::optional<Change> current_;
  std::optional<Clock::time_point> deadline_;
};

}  // namespace unima::remote
