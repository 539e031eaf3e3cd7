// values::raw_of and values::accepted: the inverse of read_word (SPEC §17).

#include "values/value_codec.hpp"

#include <cmath>

#include <fmt/format.h>

namespace unima::values {

namespace {

// A written value and a reading are the same when they differ by binary noise only: a
// millionth of a step is far below any fraction a person means and far above the error of
// a decimal in a double (about 1e-16 of it).
constexpr double same_within_steps = 1e-6;

// The whole numbers the register (or its bits) holds for `def`, before scaling.
struct WordRange {
  double lowest;
  double highest;
};

WordRange word_range(const ValueDef& def) {
  if (def.decoding == Decoding::bit_field) return {0.0, static_cast<double>((1u << (def.last_bit - def.first_bit + 1u)) - 1u)};
  if (def.decoding == Decoding::analog && def.is_signed) return {-32768.0, 32767.0};
  return {0.0, 65535.0};
}

double step_of(const ValueDef& def) { return def.decoding == Decoding::analog ? def.scale : 1.0; }

// The number a reading is, a boolean as 0 or 1; nullopt for a null one.
std::optional<double> number_of(const Value& reading) {
  if (const auto* number = std::get_if<double>(&reading.reading)) return *number;
  if (const auto* flag = std::get_if<bool>(&reading.reading)) return *flag ? 1.0 : 0.0;
  return std::nullopt;
}

double reading_of(const ValueDef& def, std::uint16_t word) { return number_of(read_word(def, word)).value_or(0.0); }

}  // namespace

std::uint16_t word_mask(const ValueDef& def) {
  if (def.decoding != Decoding::bit_field) return 0xFFFF;
  const unsigned width = def.last_bit - def.first_bit + 1u;
  return static_cast<std::uint16_t>(((1u << width) - 1u) << def.first_bit);
}

bool writable(const ValueDef& def) {
  return def.decoding == Decoding::analog || def.decoding == Decoding::word || def.decoding == Decoding::bit_field;
}

std::optional<Accepted> accepted(const ValueDef& def) {
  if (!writable(def)) return std::nullopt;
  const auto range = word_range(def);
  if (def.decoding != Decoding::analog) return Accepted{range.lowest, range.highest, 1.0};
  // The readings of the extreme words, so that the range is printed as a reading is.
  if (def.is_signed) return Accepted{reading_of(def, 0x8000), reading_of(def, banks::not_measured - 1), def.scale};
  return Accepted{reading_of(def, 0), reading_of(def, 0xFFFF), def.scale};
}

Encoded raw_of(const ValueDef& def, double value, std::uint16_t register_now) {
  if (!writable(def)) return fmt::format("{} is read only", def.name);
  const auto range = *accepted(def);
  if (!std::isfinite(value)) return fmt::format("{} takes a number, not {}", def.name, value);
  const double steps = value / step_of(def);
  const double whole = std::round(steps);
  const auto words = word_range(def);
  if (whole < words.lowest || whole > words.highest)
    return fmt::format("{} takes {}…{}, not {}", def.name, range.min, range.max, value);
  if (std::abs(steps - whole) > same_within_steps)
    return fmt::format("{} takes steps of {}, and {} is between two", def.name, range.step, value);
  auto word = static_cast<std::uint16_t>(static_cast<std::int32_t>(whole) & 0xFFFF);
  if (def.decoding == Decoding::bit_field)
    word = static_cast<std::uint16_t>((register_now & ~word_mask(def)) | (word << def.first_bit));
  // Read back by the one decoding: only what reads as itself is written.
  const auto back = number_of(read_word(def, word));
  if (!back) return fmt::format("{} = {} would be the word 0x{:04X}, which reads as not measured", def.name, value, word);
  if (std::abs(*back - value) > same_within_steps * range.step)
    return fmt::format("{} = {} would read back as {}", def.name, value, *back);
  return word;
}

}  // namespace unima::values
