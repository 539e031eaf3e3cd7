#pragma once
// What a register means for everything that is not Modbus (SPEC §17): the page,
// /api/registers and MQTT read named, typed values, decoded here once from the device
// tables and the mapping, never by each of them apart. The layout is built once per
// config; evaluating a bank turns a snapshot of its raw registers into its values.
// Pure: the callers pass the registers in (values/store_snapshot.hpp reads them).

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "banks/bank_id.hpp"
#include "banks/source_ref.hpp"

namespace unima::config {
struct Config;
}

namespace unima::values {

/// Why a value is what it is; every state but `ok` comes with a null reading.
enum class State : std::uint8_t { ok, not_measured, offline, not_set, not_mapped };

enum class ValueType : std::uint8_t { number, boolean, text };

/// How a value is read from its registers.
enum class Decoding : std::uint8_t {
  analog,      // raw (two's complement when signed) × scale; 0x7FFF is not measured
  pair32,      // (high × 65536 + low) × scale; offsets {low, high}
  byte_field,  // one byte of a byte pair × its own scale; 255 is not measured
  word,        // a bit word as a whole number
  bit_field,   // bits first..last of a bit word: a boolean for one bit, else a number
  ascii,       // two characters, in the order of the table's fields
  mapped,      // bank A: an entry in its source's unit; not mapped without a source
  mapped_bit,  // bank B: bit first_bit, as a boolean; not mapped without a source
};

/// One value of a bank: its name, type, unit and the registers it reads.
struct ValueDef {
  std::string name;   // "engine_speed", "operating_hours", "knock_rank_1.level", "D1.oil_temperature"
  std::string label;  // the seed's Czech text, when the table has it
  std::string unit;
  ValueType type = ValueType::number;
  Decoding decoding = Decoding::analog;
  std::vector<std::uint16_t> offsets;  // the registers of its bank it reads, first the lowest
  double scale = 1.0;
  unsigned decimals = 0;  // a reading is rounded to the scale's own decimals
  bool is_signed = false;
  std::uint8_t first_bit = 0;
  std::uint8_t last_bit = 15;
  std::optional<banks::SourceRef> source;  // A and B: what the entry shows
};

struct BankValues {
  banks::BankId bank = banks::BankId::A;
  std::vector<ValueDef> values;  // in register order
};

/// A bank's registers as they are now: nullopt for a register no telegram carried (D_N,
/// S_N) or no master wrote (W, X); `online` false for a D_N or S_N that is off-line.
struct BankReading {
  std::vector<std::optional<std::uint16_t>> registers;  // by offset
  bool online = true;
};
using Snapshot = std::array<BankReading, banks::bank_count>;

using Reading = std::variant<std::monostate, double, bool, std::string>;

struct Value {
  Reading reading;  // monostate: null
  State state = State::ok;

  bool operator==(const Value&) const = default;
};

/// What one register word reads as for `def` — every decoding but a 32-bit pair, whose
/// value takes two — whatever else the bank holds (a mapped entry's source is not asked).
/// ValueModel::evaluate reads each register through it, and the way back
/// (values/value_codec) reads its answer back through it.
Value read_word(const ValueDef& def, std::uint16_t raw);

/// The decimals that tell two neighbouring readings of `def` apart — its scale's step in
/// digits (0.1 -> 1, 0.01 -> 2, 1 -> 0, 0.78125 -> 1, 0.00244 -> 3): what a display
/// shows. `decimals` is what a reading keeps so that it is exact (0.78125 -> 5), which
/// shown whole would be noise (35.15625 %). Never more than `decimals`.
unsigned display_decimals(const ValueDef& def);

class ValueModel {
 public:
  ValueModel() = default;
  explicit ValueModel(const config::Config& config);

  /// Every bank of the config that has values (a D_N without a device has none), in the
  /// order of banks::all_banks.
  const std::vector<BankValues>& banks() const { return banks_; }
  const BankValues* bank(banks::BankId bank) const;

  /// The values of `bank`, by the index of their ValueDef, from `snapshot` (which holds
  /// the sources of A and B too). Precondition: the bank has values.
  std::vector<Value> evaluate(banks::BankId bank, const Snapshot& snapshot) const;

 private:
  std::vector<BankValues> banks_;
};

}  // namespace unima::values
