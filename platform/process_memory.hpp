#pragma once
// The daemon's own resident memory, for the status document and /metrics (SPEC §13).

#include <cstdint>
#include <optional>

namespace unima::platform {

/// Resident set size in bytes (/proc/self/statm); nullopt where it cannot be read.
std::optional<std::uint64_t> resident_bytes();

}  // namespace unima::platform
