#pragma once
// The frame examples of seed 004 (the Bridge) as on the wire. Their CRCs are the seed's
// and correct (tests/unit/modbus_test.cpp checks them), so every test uses them as its
// vectors instead of writing them out again.

#include <cstdint>
#include <vector>

namespace unima::test_support::seed {

/// §5.1: slave 1, function 4, two input registers from 0x0011.
inline const std::vector<std::uint8_t> read_query = {0x01, 0x04, 0x00, 0x11, 0x00, 0x02, 0x21, 0xCE};
/// §5.1: its answer, 0x0050 and 0x7FFF (not measured).
inline const std::vector<std::uint8_t> read_response = {0x01, 0x04, 0x04, 0x00, 0x50, 0x7F, 0xFF, 0x9B, 0xE5};
/// §5.2: slave 1, function 6, 0x0929 into register 0x0101 (its echo is the same frame).
inline const std::vector<std::uint8_t> write_query = {0x01, 0x06, 0x01, 0x01, 0x09, 0x29, 0x1E, 0x78};

}  // namespace unima::test_support::seed
