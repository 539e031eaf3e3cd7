#pragma once
// Capture blocks (MBS_RegC, seed 004 §7.1, SPEC §4): on a shared RTU line the bridge
// hears the master talk to other slaves, and takes the value of register R of foreign
// device D into user analog output n, without ever answering. Pure: the RTU port hands
// in the frames it heard (whole ADUs, CRC checked), this says which outputs get which
// values. What an exchange carries is modbus/register_capture's rule.

#include <cstdint>
#include <span>
#include <vector>

namespace unima::modbus {

struct CaptureRule {
  std::uint8_t device = 0;  // the foreign slave's Modbus address
  std::uint16_t reg = 0;    // its register, protocol address
  unsigned output = 0;      // user analog output 1..16
};

struct Captured {
  enum class Via : std::uint8_t { write, read };
  unsigned output = 0;
  std::uint16_t value = 0;
  Via via = Via::write;
  bool operator==(const Captured&) const = default;
};

/// What a master's write carries to D: function 6 (seed), or 16 covering R (extension).
/// Taken from the request as soon as it is heard, not from the slave's echo. A broadcast
/// (address 0) reaches D too.
std::vector<Captured> captured_writes(std::span<const CaptureRule> rules, std::span<const std::uint8_t> query);

/// What D reported: a function-4 (seed) or 3 (extension) read whose range covers R, and
/// D's normal response to it (same address and function, the byte count the read asked
/// for). An exception response captures nothing.
std::vector<Captured> captured_reads(std::span<const CaptureRule> rules, std::span<const std::uint8_t> query,
                                     std::span<const std::uint8_t> response);

}  // namespace unima::modbus
