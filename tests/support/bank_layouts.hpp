#pragma once
// The pieces several unit tests of banks/ build a register space from: a bank's window in
// the address map, and the banks' shapes with unigen-chp (a table of every register kind)
// in the device banks a test names.

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

#include "banks/address_map.hpp"
#include "banks/bank_id.hpp"
#include "banks/register_store.hpp"
#include "banks/table_catalog.hpp"

namespace unima::banks {

/// `bank`'s window of `count` registers from `first`, named as the config names it.
inline Window bank_window(BankId bank, std::uint16_t first, std::uint16_t count, std::string origin = {}) {
  Window w;
  w.kind = Window::Kind::bank;
  w.bank = bank;
  w.first = first;
  w.count = count;
  w.name = "bank " + std::string(bank_name(bank));
  w.origin = std::move(origin);
  return w;
}

inline const DeviceTable& chp() {
  const DeviceTable* t = find_device_type("unigen-chp");
  if (!t) throw std::runtime_error("unigen-chp missing");
  return *t;
}

/// The standard shapes with `devices` in D1..D4 (nullptr: no device there).
inline BankShapes shapes_with(std::array<const DeviceTable*, 4> devices) {
  return standard_shapes(devices, io_module_table(), bridge_internal_table());
}

}  // namespace unima::banks
