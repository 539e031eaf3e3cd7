#pragma once
// What the request handler reads and writes: 16-bit registers by protocol address.

#include <cstdint>
#include <span>

namespace unima::modbus {

class RegisterModel {
 public:
  virtual ~RegisterModel() = default;
  /// Fills `out` from address `first`; false when any register is not readable.
  virtual bool read_registers(std::uint16_t first, std::span<std::uint16_t> out) = 0;
  /// Writes all of `values` from `first`, or nothing and false when any is not writable.
  virtual bool write_registers(std::uint16_t first, std::span<const std::uint16_t> values) = 0;
};

}  // namespace unima::modbus
