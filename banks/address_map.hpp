#pragma once
// Which bank (or block register) a Modbus register address belongs to. Built once per
// config; a lookup is a binary search over the sorted windows, never a scan of all banks.

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "banks/bank_id.hpp"
#include "banks/source_ref.hpp"

namespace unima::banks {

/// A run of consecutive register addresses served by one bank or one function block.
struct Window {
  enum class Kind : std::uint8_t { bank, read_block, write_block };
  Kind kind = Kind::bank;
  BankId bank = BankId::A;     // for Kind::bank
  SourceRef source;            // for Kind::read_block: the value it reads (seed MBS_RegR)
  std::uint8_t output = 0;     // for Kind::write_block: user analog output 1..16 (MBS_RegW)
  std::uint16_t first = 0;     // protocol address (0-based)
  std::uint16_t count = 0;
  std::string name;            // "bank D1", "read block 0x0200": used in overlap errors
  std::string origin;          // "bridge.yaml:4:11" where the config set it, if it did

  std::uint32_t end() const { return std::uint32_t{first} + count; }
};

class OverlapError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class AddressMap {
 public:
  AddressMap() = default;
  /// Throws OverlapError naming both windows if two overlap, or if one runs past 0xFFFF;
  /// the message starts with the origin of a window the config set, when there is one.
  explicit AddressMap(std::vector<Window> windows);

  /// The window holding `address`, or nullptr.
  const Window* find(std::uint16_t address) const;
  /// The window right after `window` if it starts exactly where `window` ends, else nullptr.
  const Window* adjacent_after(const Window& window) const;

  const std::vector<Window>& windows() const { return windows_; }

 private:
  std::vector<Window> windows_;  // sorted by first
};

}  // namespace unima::banks
