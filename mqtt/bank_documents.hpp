#pragma once
// What the bridge publishes of each bank on MQTT (SPEC §12, §17): `<prefix>/<bank>`, a
// JSON object of the bank's values (values/value_model.hpp) by their names, flat — a
// 32-bit pair as one key ("operating_hours"), a byte pair and a bit word's bits as dotted
// keys ("knock_rank_1.level", "status.state"), A and B by their mapping sources
// ("D1.oil_temperature") — with `null` for a value not measured or of an off-line device,
// and "online" and "time". Unmapped entries and reserves are left out. And when a bank is
// due: on change on the leading edge (at once after a quiet 100 ms, else when its 100 ms
// are up), and all of them every `period` and after a reconnect. Pure: values, change
// counts and time points are passed in.

#include <chrono>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "values/leading_edge.hpp"
#include "values/value_model.hpp"

namespace unima::mqtt {

/// The banks published of a value model: A, B, C, D1..D4, S1..S7 (not W or X), in the
/// model's order.
std::vector<banks::BankId> published_banks(const values::ValueModel& model);

/// "online", then the values in the table's order: what changes a bank's document.
nlohmann::ordered_json bank_values(const values::BankValues& layout, std::span<const values::Value> values, bool online);

/// The document: "time", then bank_values().
nlohmann::ordered_json bank_document(const values::BankValues& layout, std::span<const values::Value> values, bool online,
                                     std::chrono::system_clock::time_point now);

/// Which banks are due, from their change counts and the clock: each bank on the leading
/// edge (values/leading_edge.hpp) when it changes, all of them every `period` and after a
/// reconnect. Its owner asks due() when the store changed and again at next_due().
class PublishSchedule {
 public:
  using Clock = values::LeadingEdge::Clock;
  static constexpr std::chrono::milliseconds min_interval = values::LeadingEdge::cap;
  /// Bank i's state: its values and on-line state, in a form compared as a whole.
  using StateOf = std::function<std::string(std::size_t bank)>;

  PublishSchedule(std::size_t banks, std::chrono::milliseconds period, bool on_change);

  /// Everything again at the next call (a new connection: retained documents are refreshed).
  void publish_all() { all_due_ = true; }
  /// The banks to publish now; `changes[i]` counts bank i's changes
  /// (banks::RegisterStore::changes). A bank whose count moved goes when its leading edge
  /// allows, if its state then differs from the one last published; `state_of` is asked
  /// only of banks that may go now, and what it says of a bank that goes is remembered as
  /// published.
  std::vector<std::size_t> due(std::span<const std::uint64_t> changes, Clock::time_point now, const StateOf& state_of);
  /// When due() has work without a new change: a changed bank's 100 ms are up, or the period.
  Clock::time_point next_due() const { return next_due_; }

 private:
  struct Bank {
    std::string published;        // the state last published
    values::LeadingEdge edge;
    std::uint64_t examined = 0;   // the change count when its state was last compared
    std::uint64_t latest = 0;     // the change count due() saw last
  };
  std::chrono::milliseconds period_;
  bool on_change_;
  bool all_due_ = true;
  Clock::time_point last_full_{};
  Clock::time_point next_due_{};
  std::vector<Bank> banks_;
};

}  // namespace unima::mqtt
