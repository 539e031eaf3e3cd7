#pragma once
// All register tables the daemon knows: the nine D_N device types (SPEC §2), the IO module
// of S_N and the Bridge's own bank C, from the embedded files. Each table is parsed once,
// when it is first asked for; a parsed table stays put for the life of the process.

#include <string_view>
#include <vector>

#include "banks/device_table.hpp"

namespace unima::banks {

/// Every table, in id order (parses those not parsed yet). Throws TableError if an
/// embedded file is invalid.
std::vector<const DeviceTable*> all_tables();

/// A D_N device type by its id or alias (`unigen-chp`, `microgen-chp`); nullptr if unknown.
const DeviceTable* find_device_type(std::string_view id);

/// The ids (not aliases) of the device types a D_N bank can select.
std::vector<std::string_view> device_type_ids();

inline constexpr std::string_view io_module_table_id = "io-module";
inline constexpr std::string_view bridge_internal_table_id = "bridge-internal";

/// The table of an S_N bank, or nullptr when the build carries none.
const DeviceTable* io_module_table();
/// The table of bank C, or nullptr when the build carries none.
const DeviceTable* bridge_internal_table();

}  // namespace unima::banks
