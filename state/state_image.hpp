#pragma once
// The values a restart must bring back (SPEC §10): what Modbus masters wrote into W and X
// and into the user outputs of write blocks (MBS_RegW). A value never written is unset:
// W reads 0x7FFF and X 0 until a master writes them, and the feed snapshot leaves them out.

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

namespace unima::state {

/// One value to keep: W+index, X (index 0), or user output `index` (1..16) of a write block.
struct PersistedValue {
  enum class Kind : char { w = 'W', x = 'X', output = 'O' };
  Kind kind = Kind::w;
  std::uint16_t index = 0;
  std::uint16_t value = 0;

  friend bool operator==(const PersistedValue&, const PersistedValue&) = default;
};

inline constexpr std::uint16_t w_registers = 16;
inline constexpr std::uint16_t x_registers = 1;
inline constexpr std::uint16_t user_outputs = 16;

/// True when `kind` has a register numbered `index` (W 0..15, X 0, outputs 1..16).
bool valid_index(PersistedValue::Kind kind, std::uint16_t index);

class StateImage {
 public:
  /// Precondition: valid_index(value.kind, value.index).
  void apply(const PersistedValue& value);
  std::optional<std::uint16_t> w(std::uint16_t offset) const { return w_[offset]; }
  std::optional<std::uint16_t> x() const { return x_; }
  std::optional<std::uint16_t> output(unsigned n) const { return outputs_[n - 1]; }
  /// Every set value, W first, then X, then the outputs: what a compacted journal holds.
  std::vector<PersistedValue> values() const;
  bool empty() const { return values().empty(); }

  friend bool operator==(const StateImage&, const StateImage&) = default;

 private:
  std::array<std::optional<std::uint16_t>, w_registers> w_{};
  std::optional<std::uint16_t> x_;
  std::array<std::optional<std::uint16_t>, user_outputs> outputs_{};
};

}  // namespace unima::state
