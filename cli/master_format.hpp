#pragma once
// What `unima-bridge check` prints for a master config — the merge plan, which blocks
// share a request at which period, and the estimated bus load — and what
// `unima-bridge profiles` prints about the device profiles.

#include <string>
#include <string_view>

#include "config/config.hpp"

namespace unima::cli {

/// The plan of a config in master mode, with warnings (a device asked more often than it
/// can answer, a line over its capacity) at the end.
std::string format_master_plan(const config::Config& config);

/// Each line of a config with several (SPEC §18), one row each: role, device and
/// character format, t3.5, and the slave's address or the gateway's units. Empty with one
/// line or none, whose plan reads as before lines had names.
std::string format_lines(const config::Config& config);

/// Every profile in one line each; with `id`, the points of that profile. Empty when `id`
/// names no profile.
std::string format_profiles(std::string_view id);

}  // namespace unima::cli
