#pragma once
// Values of foreign slaves and the bridge's 16-bit registers (SPEC §4 extensions): data
// types over one or two registers, the word order of 32-bit values, and scaling into the
// bridge's 0.1-unit registers. Pure.

#include <cstdint>
#include <optional>
#include <span>

#include "banks/bank_id.hpp"
#include <string_view>

namespace unima::master {

/// What a point of a foreign slave holds. `bits`: coils or discrete inputs (functions 1,
/// 2, 5); the others are registers: WORD (unsigned) and INT (signed) in one, DINT (signed),
/// DWORD (unsigned) and REAL (IEEE 754 single) in two — the names of seeds 000 and 001.
enum class ValueType : std::uint8_t { bits, word, int16, dint, dword, real };

/// Which register of a 32-bit value comes first. All three foreign seeds put the low word
/// first (seed 000 §4.1, seed 001 §3.2, seed 002 note 2); bytes within a register are
/// always high byte first (Modbus Application Protocol V1.1b3 §4.2).
enum class WordOrder : std::uint8_t { low_first, high_first };

std::string_view value_type_name(ValueType type);  // "bits", "word", "int", "dint", "dword", "real"
std::optional<ValueType> parse_value_type(std::string_view name);
std::string_view word_order_name(WordOrder order);  // "low_first", "high_first"
std::optional<WordOrder> parse_word_order(std::string_view name);

/// Registers a value takes: 1 or 2; 0 for bits (they are counted in coils).
unsigned register_span(ValueType type);
bool is_signed(ValueType type);

/// The value held in `registers` (register_span(type) of them).
double decode_value(ValueType type, WordOrder order, std::span<const std::uint16_t> registers);
/// `value` as `type` into `registers` (register_span(type) of them): rounded to the
/// nearest integer and clamped to the type's range for the integer types.
void encode_value(ValueType type, WordOrder order, double value, std::span<std::uint16_t> registers);

/// The "not measured" value of an analog register (SPEC §1), decided in banks/.
using banks::not_measured;

/// A device value as a bridge register: value × scale, rounded, clamped to −32768..32766
/// when `signed_result` (32767 would read "not measured") or to 0..65535 when not. NaN
/// reads not measured.
std::uint16_t to_bridge_register(double device_value, double scale, bool signed_result);
/// A bridge register as a device value: raw (two's complement when `signed_source`) ÷ scale.
double from_bridge_register(std::uint16_t raw, bool signed_source, double scale);

}  // namespace unima::master
