#pragma once
// The register values an exchange carried on the bus — the one rule behind the capture
// indicators (seed 004 §8) and the capture blocks (SPEC §4, modbus/capture): the written
// values of functions 6 and 16 (from the query), the read values of functions 3 and 4
// (from the response to that query: same address, same function, the byte count asked
// for). Works for any address, so Not4Me traffic between a foreign master and slave is
// captured too. Pure.

#include <cstdint>
#include <optional>
#include <span>

#include "modbus/adu_view.hpp"
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

/// What the exchange of `query` and `response` (empty when none was heard) carried, or
/// nullopt: a write counts from its query alone, whatever followed (its value was on the
/// bus; a broadcast has no answer); a read needs its own normal response; an exception
/// response carries nothing.
std::optional<CapturedRegisters> exchange_registers(const AduView& query, const AduView& response);

/// What `transaction` carried (exchange_registers), or nullopt: only Done and Not4Me transactions count, never
/// one answered with an exception; a read needs a response whose byte count fits the
/// query. A write whose response was not heard (broadcast, Not4Me) still counts: its
/// value was on the bus.
std::optional<CapturedRegisters> captured_registers(const Transaction& transaction);

}  // namespace unima::modbus
