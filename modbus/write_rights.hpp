#pragma once
// Which registers a client may write (SPEC §11): all of them on a plain port, none on a
// read-only one, and on Modbus/TCP Security what its certificate's role lists. A write
// that touches a register outside them is answered with exception 01 (illegal function)
// and changes nothing: the request handler asks before it writes. Reads are never limited.
//
// Pure: the ranges come from the config (config/access), the client's role from its port.

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

  /// True when every register of first..first+count-1 may be written.
  bool allows(std::uint16_t first, std::uint16_t count) const;
  bool allows_everything() const { return everything_; }
  bool allows_nothing() const { return !everything_ && ranges_.empty(); }
  /// first..last ranges, sorted, none overlapping or adjacent to another.
  const std::vector<std::pair<std::uint16_t, std::uint16_t>>& ranges() const { return ranges_; }

  bool operator==(const WriteRights&) const = default;

 private:
  explicit WriteRights(bool everything) : everything_(everything) {}
  bool everything_;
  std::vector<std::pair<std::uint16_t, std::uint16_t>> ranges_;
};

}  // namespace unima::modbus
