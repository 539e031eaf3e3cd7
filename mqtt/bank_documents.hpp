#pragma once
// What the bridge publishes of each bank on MQTT (SPEC §12): `<prefix>/<bank>`, a JSON
// object of the bank's registers by their table identifiers (A and B: by their mapping
// source, as the config writes it) in engineering units — raw × scale, `null` for an
// analog register's 0x7FFF ("not measured") — with "online" and "time". And when a bank
// is due: on change, at most every 100 ms, and all of them every `period` and after a
// reconnect. Pure: values and time points are passed in.

#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "banks/source_ref.hpp"
#include "config/register_map.hpp"

namespace unima::mqtt {

struct BankRegister {
  std::string key;   // table identifier, or the mapping source for A and B
  std::string kind;  // analog, bits, ...
  double scale = 1.0;
  std::size_t row = 0;  // index into the register map's rows (and so into a values vector)
  std::optional<unsigned> bit;  // B: one mapped bit of the register, 0 or 1
};

struct BankLayout {
  std::string bank;  // "D1", "A", ...
  std::vector<BankRegister> registers;
};

/// The published banks of a register map (A, B, C, D1..D4, S1..S7; not W, X or blocks), in
/// the map's order; A's mapped registers and B's mapped bits keyed by their sources in
/// `mapping` (B's bits one entry each).
std::vector<BankLayout> bank_layouts(const std::vector<config::MapRow>& rows, const banks::Mapping& mapping);

/// One register's value as published: a number in engineering units, or null.
nlohmann::json engineering_value(const BankRegister& reg, std::optional<std::uint16_t> raw);

/// The document of `layout` ("time", "online", then the registers in the table's order);
/// `values` are the register map's, by row.
nlohmann::ordered_json bank_document(const BankLayout& layout, std::span<const std::optional<std::uint16_t>> values, bool online,
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
