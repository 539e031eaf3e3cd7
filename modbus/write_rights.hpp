#pragma once
// Which registers a client may write (SPEC §11): all of them on a plain port, none on a
// read-only one, and on Modbus/TCP Security what its certificate's role lists. A write
// that touches a register outside them is answered with exception 01 (illegal function)
// and changes nothing: the request handler asks before it writes. Reads are never limited.
// The same holds for the foreign slaves behind the gateway (SPEC §14): a role names the
// unit ids it may send writes to ("unit 3", "units 5-9"), and the port asks may_forward
// before a request goes on the line.
//
// Pure: the ranges come from the config (config/access), the client's role from its port.

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace unima::modbus {

class WriteRights {
 public:
  /// Every register the register map lets be written.
  static WriteRights everything() { return WriteRights(true); }
  /// No register: a read-only client.
  static WriteRights nothing() { return WriteRights(false); }

  /// Adds first..last (inclusive).
  void allow(std::uint16_t first, std::uint16_t last);

  /// Adds the unit ids first..last (inclusive) of the foreign slaves behind the gateway.
  void allow_units(std::uint8_t first, std::uint8_t last);

  /// True when every register of first..first+count-1 may be written.
  bool allows(std::uint16_t first, std::uint16_t count) const;
  /// True when a request with `function` may go to the foreign slave `unit`: a read
  /// (functions 1-4) always, any other function only to a unit these rights name.
  bool may_forward(std::uint8_t unit, std::uint8_t function) const;
  bool allows_everything() const { return everything_; }
  bool allows_nothing() const;
  /// first..last ranges, sorted, none overlapping or adjacent to another.
  const std::vector<std::pair<std::uint16_t, std::uint16_t>>& ranges() const { return ranges_; }

  bool operator==(const WriteRights&) const = default;

 private:
  explicit WriteRights(bool everything) : everything_(everything) {}
  bool everything_;
  std::vector<std::pair<std::uint16_t, std::uint16_t>> ranges_;
  std::array<bool, 256> units_{};  // by unit id: writes may be forwarded to it
};

}  // namespace unima::modbus
