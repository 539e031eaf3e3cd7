#pragma once
// What the request handler reads and writes: 16-bit registers by protocol address.

#include <cstdint>
#include <span>

#include "modbus/write_rights.hpp"

namespace unima::modbus {

/// What became of a write, as the one who took it says (for the bridge, banks::WritePath).
struct WriteResult {
  enum class Status : std::uint8_t {
    written,       // every value was taken
    not_allowed,   // the client's rights do not cover every register: exception 01
    not_writable,  // a register of the range is not writable: exception 02
    read_only,     // the bridge takes no writes at all (modbus.tcp.read_only): exception 01
    not_kept,      // taken, but the state file could not keep it, so nothing changed
                   // (SPEC §10): exception 04. Known only after the answer was built, so
                   // the port answers it with modbus::answer_refused_write.
  };
  Status status = Status::written;
  /// The number under which the values were kept for a restart: the write may be
  /// acknowledged only once that is durable. 0: nothing was kept, answer at once.
  std::uint64_t kept_as = 0;
};

class RegisterModel {
 public:
  virtual ~RegisterModel() = default;
  /// Fills `out` from address `first`; false when any register is not readable.
  virtual bool read_registers(std::uint16_t first, std::span<std::uint16_t> out) = 0;
  /// Writes all of `values` from `first`, or nothing when `rights` (nullptr: every
  /// register) do not cover them all or any is not writable.
  virtual WriteResult write_registers(std::uint16_t first, std::span<const std::uint16_t> values,
                                      const WriteRights* rights) = 0;
};

}  // namespace unima::modbus
