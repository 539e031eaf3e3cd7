#pragma once
// CRC-32 (IEEE 802.3, as zlib and `crc32` compute it): each state journal record carries
// one, so that a record torn or damaged on the disk is never taken for a value.

#include <cstdint>
#include <string_view>

namespace unima::state {

std::uint32_t crc32(std::string_view bytes);

}  // namespace unima::state
