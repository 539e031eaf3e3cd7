#pragma once
// Bytes as the monitor shows them: two upper-case hex digits and a space each ("04 00 11 ").
// Most of a monitor line is this text (a 64-register response is 137 bytes), so where the
// CPU has a byte shuffle (SSSE3, checked once at run time: Debian's amd64 baseline lacks
// it) sixteen bytes are done at a time.

#include <cstddef>
#include <cstdint>

namespace unima::monitor {

/// Writes the two digits of one byte ("0A"); returns out + 2.
char* write_hex_digits(char* out, std::uint8_t byte);

/// Writes "XX " for each of the `size` bytes at `out`, which has room for 3 * size + 1
/// bytes (a spare byte after the last space may be overwritten). Returns out + 3 * size.
char* write_hex_cells(char* out, const std::uint8_t* bytes, std::size_t size);

namespace hex_text_detail {
// Both ways, for the tests: the portable one, and the vector one where the CPU has it.
char* write_hex_cells_portable(char* out, const std::uint8_t* bytes, std::size_t size);
bool vector_way_available();
char* write_hex_cells_vector(char* out, const std::uint8_t* bytes, std::size_t size);
}  // namespace hex_text_detail

}  // namespace unima::monitor
