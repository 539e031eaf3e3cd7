#pragma once
// When each bank's report goes (SPEC §12, §21): a bank whose values changed — by the
// change rule (report/change_rule) against what its last document published, so a move
// within the deadband is no change — goes on the leading edge: at once when its last
// document is `min_interval` old, else when it is, with the values it has then (never a
// backlog). Every bank goes in full at least every `max_interval` after its last
// document, and all of them after a reconnect. A document carries a bank's values as they
// are (a move within the deadband rides along with the next document that goes); what it
// carried is what the next comparison is against. MQTT's bank documents and Sparkplug's
// DDATA (sparkplug/edge_session, one schedule per node) both go by it. Pure: change
// counts, values and time points are passed in.

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "values/value_model.hpp"

namespace unima::report {

struct Intervals {
  std::chrono::milliseconds min_interval{100};
  std::chrono::milliseconds max_interval{10'000};
  bool on_change = true;  // false: only every max_interval (mqtt.publish.on_change)
};

class ReportSchedule {
 public:
  using Clock = std::chrono::steady_clock;
  /// A bank as it is now: its values (ValueModel::evaluate's), on-line state and deadbands
  /// (report::Deadbands::of; empty: 0 for all).
  struct BankNow {
    std::span<const values::Value> values;
    bool online = true;
    std::span<const double> deadbands;
  };
  using BankNowOf = std::function<BankNow(std::size_t bank)>;

  ReportSchedule(std::size_t banks, Intervals intervals);

  /// Everything again at the next call (a new connection: retained documents are refreshed).
  void publish_all() { all_due_ = true; }
  /// `bank` goes at the next call its min_interval allows, changed or not (Sparkplug: a
  /// value a refused command left as it was, told to the host again).
  void republish(std::size_t bank) { banks_.at(bank).asked = true; }
  /// The banks to publish now; `changes[i]` counts bank i's changes
  /// (banks::RegisterStore::changes). A bank whose count moved goes when its
  /// min_interval allows, if a value then counts as changed (or its on-line state
  /// changed), and one republish() asked for goes then whatever it holds; a bank whose
  /// max_interval is up goes in full. `bank_now` is asked only of
  /// banks that may go now, and what it says of a bank that goes is remembered as published.
  std::vector<std::size_t> due(std::span<const std::uint64_t> changes, Clock::time_point now, const BankNowOf& bank_now);
  /// When due() has work without a new change: a held-back bank's min_interval, or the
  /// first max_interval that is up.
  Clock::time_point next_due() const { return next_due_; }
  const Intervals& intervals() const { return intervals_; }
  /// Whether `bank`, when it last went, went in full (all due, its first document, or its
  /// max_interval up) rather than for a change: a Sparkplug DDATA then carries every metric.
  bool went_in_full(std::size_t bank) const { return banks_.at(bank).in_full; }

 private:
  struct Bank {
    std::vector<values::Value> published;  // what its last document carried
    bool published_online = false;
    std::optional<Clock::time_point> went;  // its last document; none yet: it goes now
    std::uint64_t examined = 0;             // the change count when its values were last compared
    std::uint64_t latest = 0;               // the change count due() saw last
    bool asked = false;                     // republish(): goes at its next chance, changed or not
    bool in_full = false;                   // its last document went in full
  };
  static bool changed(const Bank& bank, const BankNow& now);

  Intervals intervals_;
  bool all_due_ = true;
  Clock::time_point next_due_{};
  std::vector<Bank> banks_;
};

}  // namespace unima::report
