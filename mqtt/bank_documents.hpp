#pragma once
// What the bridge publishes of each bank on MQTT (SPEC §12, §17): `<prefix>/<bank>`, a
// JSON object of the bank's values (values/value_model.hpp) by their names, flat — a
// 32-bit pair as one key ("operating_hours"), a byte pair and a bit word's bits as dotted
// keys ("knock_rank_1.level", "status.state"), A and B by their mapping sources
// ("D1.oil_temperature") — with `null` for a value not measured or of an off-line device,
// and "online" and "time". Unmapped entries and reserves are left out. And when a bank is
// due: on change, at most every 100 ms, and all of them every `period` and after a
// reconnect. Pure: values and time points are passed in.

#include <chrono>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

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

/// Which banks are due, from their values and the clock.
class PublishSchedule {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr std::chrono::milliseconds min_interval{100};

  PublishSchedule(std::size_t banks, std::chrono::milliseconds period, bool on_change);

  /// Everything again at the next call (a new connection: retained documents are refreshed).
  void publish_all() { all_due_ = true; }
  /// The banks to publish now, given each bank's current state (its values and on-line
  /// state, in a form compared as a whole); their states are remembered as published.
  std::vector<std::size_t> due(const std::vector<std::string>& states, Clock::time_point now);

 private:
  std::chrono::milliseconds period_;
  bool on_change_;
  bool all_due_ = true;
  Clock::time_point last_full_{};
  std::vector<std::string> published_;
  std::vector<Clock::time_point> published_at_;
};

}  // namespace unima::mqtt
