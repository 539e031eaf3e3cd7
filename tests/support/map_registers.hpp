#pragma once
// A register model over two maps, for the tests of the request handler and the ports: an
// address missing from `readable` (or, for a write, from `writable`) fails the whole
// request, like a register the bridge does not have. A write asks the rights first and
// changes all or nothing, as banks::WritePath does.

#include <cstdint>
#include <map>
#include <span>
#include <utility>

#include "modbus/register_model.hpp"

namespace unima::test_support {

class MapRegisters : public modbus::RegisterModel {
 public:
  using Values = std::map<std::uint16_t, std::uint16_t>;
  MapRegisters(Values readable_values, Values writable_values)
      : readable(std::move(readable_values)), writable(std::move(writable_values)) {}

  bool read_registers(std::uint16_t first, std::span<std::uint16_t> out) override {
    ++reads;
    for (std::size_t i = 0; i < out.size(); ++i) {
      const auto it = readable.find(static_cast<std::uint16_t>(first + i));
      if (it == readable.end()) return false;
      out[i] = it->second;
    }
    return true;
  }
  // As banks::WritePath: the rights first, then all or nothing; nothing is kept.
  modbus::WriteResult write_registers(std::uint16_t first, std::span<const std::uint16_t> values,
                                      const modbus::WriteRights* rights) override {
    using Status = modbus::WriteResult::Status;
    if (rights && !rights->allows(first, static_cast<std::uint16_t>(values.size()))) return {Status::not_allowed};
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!writable.contains(static_cast<std::uint16_t>(first + i))) return {Status::not_writable};
    for (std::size_t i = 0; i < values.size(); ++i) writable[static_cast<std::uint16_t>(first + i)] = values[i];
    return {Status::written};
  }

  Values readable;
  Values writable;
  int reads = 0;  // calls of read_registers
};

}  // namespace unima::test_support
