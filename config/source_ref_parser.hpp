#pragma once
// Parses source references (SPEC §7): `D1+0x21`, `D1.oil_temperature`, `S1+0x00`, `W+0x03`,
// `C+0x00`, and bits `D1+0x15.3`, `X.0`, `D1.remote_start` (a single-bit field by name).

#include <string_view>
#include <variant>

#include "banks/register_store.hpp"
#include "banks/source_ref.hpp"

namespace unima::config {

enum class SourceUse {
  analog,       // bank A entries, read and send blocks: a whole register
  bit,          // bank B, user inputs and outputs: one bit
};

/// The reference, or why it is not one. `shapes` tells which banks exist and their tables.
std::variant<banks::SourceRef, std::string> parse_source_ref(std::string_view text, const banks::BankShapes& shapes,
                                                             SourceUse use);

}  // namespace unima::config
