#pragma once
// Whether a foreign slave reached through the gateway answers (SPEC §14, docs/gateway.md,
// "Seen and counted"): after `failures_to_silent` forwarded transactions in a row that got
// no answer — a time-out or a bad frame (a bad CRC, too short, another address) — the unit
// is "not answering" since the first of them; its first answer makes it "answering" again.
// A slave's exception is an answer: the slave is there. One lost frame on a noisy line is
// not a dead slave, so one failure alone changes nothing; three in a row are.
// Pure: the caller passes the time of each transaction and logs the transitions.

#include <chrono>
#include <optional>

namespace unima::master {

class UnitAnswering {
 public:
  using Time = std::chrono::system_clock::time_point;
  static constexpr unsigned failures_to_silent = 3;

  enum class Transition { none, stopped_answering, answers_again };

  /// The slave answered (data or its exception).
  Transition answered();
  /// A forwarded transaction to the slave, sent at `sent`, got no good frame back.
  Transition failed(Time sent);

  bool answering() const { return !silent_since_; }
  /// The first failure of the run that made the unit "not answering"; nullopt while it answers.
  std::optional<Time> silent_since() const { return silent_since_; }

 private:
  unsigned failures_in_a_row_ = 0;
  std::optional<Time> first_failure_;
  std::optional<Time> silent_since_;
};

}  // namespace unima::master
