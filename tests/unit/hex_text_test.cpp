// The monitor's hex text (monitor/hex_text.hpp): both ways — the portable one and the
// vector one where this CPU has it — write exactly "XX " per byte, for every length
// around the vector width and every byte value, and nothing past their room.

#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "monitor/hex_text.hpp"

namespace unima::monitor {
namespace {

using Writer = char* (*)(char*, const std::uint8_t*, std::size_t);

std::string expected_text(const std::vector<std::uint8_t>& bytes) {
  std::string text;
  char cell[4];
  for (const auto b : bytes) {
    std::snprintf(cell, sizeof cell, "%02X ", b);
    text += cell;
  }
  return text;
}

void expect_exact(Writer write, const char* way) {
  for (std::size_t size = 0; size <= 80; ++size) {
    std::vector<std::uint8_t> bytes(size);
    for (std::size_t i = 0; i < size; ++i) bytes[i] = static_cast<std::uint8_t>(i * 37 + size * 101);
    // Room for 3 * size + 1, then guard bytes that must stay untouched.
    std::string room(3 * size + 1 + 16, '#');
    char* const end = write(room.data(), bytes.data(), size);
    ASSERT_EQ(end, room.data() + 3 * size) << way << ", " << size << " bytes";
    EXPECT_EQ(room.substr(0, 3 * size), expected_text(bytes)) << way << ", " << size << " bytes";
    EXPECT_EQ(room.substr(3 * size + 1), std::string(16, '#')) << way << " wrote past its room, " << size << " bytes";
  }
}

TEST(HexText, ThePortableWayWritesEveryLengthExactly) {
  expect_exact(hex_text_detail::write_hex_cells_portable, "portable");
}

TEST(HexText, TheVectorWayWritesEveryLengthExactly) {
  if (!hex_text_detail::vector_way_available()) GTEST_SKIP() << "this CPU has no SSSE3";
  expect_exact(hex_text_detail::write_hex_cells_vector, "vector");
}

TEST(HexText, EveryByteValueHasItsDigits) {
  std::vector<std::uint8_t> all(256);
  for (std::size_t b = 0; b < all.size(); ++b) all[b] = static_cast<std::uint8_t>(b);
  std::string room(3 * all.size() + 1, '#');
  write_hex_cells(room.data(), all.data(), all.size());
  EXPECT_EQ(room.substr(0, 3 * all.size()), expected_text(all));
  char digits[2];
  EXPECT_EQ(write_hex_digits(digits, 0xA7), digits + 2);
  EXPECT_EQ(std::string(digits, 2), "A7");
}

}  // namespace
}  // namespace unima::monitor
