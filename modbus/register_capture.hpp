#pragma once
// The register values a transaction carried on the bus, for the capture indicators
// (seed 004 §8) and capture blocks (SPEC §4): the written values of functions 6 and 16
// (from the query), the read values of functions 3 and 4 (from the response). Works for
// any address, so Not4Me traffic between a foreign master and slave is captured too. Pure.

#include <cstdint>
#include <optional>
#include <span>

#include "modbus/transaction.hpp"

namespace unima::modbus {

enum class CaptureAccess : std::uint8_t { read, write };

struct CapturedRegisters {
  std::uint8_t address = 0;  // unit id or slave address of the query
  std::uint16_t first = 0;
  std::span<const std::uint8_t> data;  // two bytes per register, high byte first
  CaptureAccess access = CaptureAccess::read;

  std::size_t count() const { return data.size() / 2; }
  /// The value of register `reg` when this block covers it.
  std::optional<std::uint16_t> value_of(std::uint16_t reg) const;
};

/// What `transaction` carried, or nullopt: only Done and Not4Me transactions count, never
/// one answered with an exception; a read needs a response whose byte count fits the
/// query. A write whose response was not heard (broadcast, Not4Me) still counts: its
/// value was on the bus.
std::optional<CapturedRegisters> captured_registers(const Transaction& transaction);

}  // namespace unima::modbus
