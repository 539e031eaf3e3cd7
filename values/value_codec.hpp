#pragma once
// The way back (SPEC §17, last bullet): a value written in its unit — a Sparkplug DCMD, a
// Home Assistant number — becomes its register by the inverse of the rule ValueModel reads
// it by, and only when that register reads back as the value written. So a write cannot
// store 0x7FFF where it means "not measured", wrap past the register's range (W's 6553.5
// would be 0xFFFF, read as −0.1), or lose a fraction finer than the scale (12.34 into
// tenths). What a definition accepts (min, max, step) comes from the same rule, for those
// who announce it (Home Assistant's number entities). Pure.

#include <cstdint>
#include <optional>
#include <string>
#include <variant>

#include "values/value_model.hpp"

namespace unima::values {

/// What a value definition accepts, in its unit: min…max in steps of `step`. For an
/// unsigned analog value the word 0x7FFF inside that range is refused too (it means "not
/// measured"); a signed one has it at the top, so `max` is one step below it.
struct Accepted {
  double min = 0;
  double max = 0;
  double step = 1;
};

/// The register word, or why the value cannot be written (a sentence that names it).
using Encoded = std::variant<std::uint16_t, std::string>;

/// Whether values of `def` are written by number: a one-register analog value, a word, a
/// bit field (X, W). A 32-bit pair, a byte of a byte pair, text and mapped entries are not.
bool writable(const ValueDef& def);

/// What `def` accepts; nullopt when it is not writable.
std::optional<Accepted> accepted(const ValueDef& def);

/// The bits of its register a value of `def` is: a bit field's, else the whole word.
std::uint16_t word_mask(const ValueDef& def);

/// The word whose reading (read_word) is `value`, or the reason there is none. A bit field
/// is put into `register_now`, the other bits kept; any other definition takes the whole
/// word. `value` matches a reading within a millionth of a step: the binary noise of a
/// decimal (0.1 + 0.2), never a finer fraction.
Encoded raw_of(const ValueDef& def, double value, std::uint16_t register_now = 0);

}  // namespace unima::values
