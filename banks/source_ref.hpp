#pragma once
// A reference to a register (or one bit of it) of a bank: what mapping entries and blocks
// take their value from (SPEC §7: `D1+0x21`, `D1.oil_temperature`, `X.0`, `D1+0x15.3`).

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "banks/bank_id.hpp"

namespace unima::banks {

struct SourceRef {
  BankId bank = BankId::A;
  std::uint16_t offset = 0;
  std::optional<std::uint8_t> bit;  // set for bit sources
  std::string text;                 // as written in the config, for messages and the map

  friend bool operator==(const SourceRef& a, const SourceRef& b) {
    return a.bank == b.bank && a.offset == b.offset && a.bit == b.bit;
  }
};

/// What banks A, B and C+0x10/+0x12 show (seed §6.2.1–§6.2.3): entry n reads its source.
struct Mapping {
  static constexpr std::size_t entries = 16;
  std::array<std::optional<SourceRef>, entries> analog;        // bank A, registers 0..15
  std::array<bool, entries> analog_raw{};                      // bank A entries copied unconverted
  std::array<std::optional<SourceRef>, entries> bits;          // bank B, bits 0..15
  std::array<std::optional<SourceRef>, entries> user_inputs;   // C+0x10, bits 0..15
  std::array<std::optional<SourceRef>, entries> user_outputs;  // C+0x12, bits 0..15
};

}  // namespace unima::banks
