#include "monitor/hex_text.hpp"

#include <array>
#include <cstring>

#if defined(__x86_64__) || defined(__i386__)
#include <tmmintrin.h>
#define UNIMA_HEX_SSSE3 1
#endif

namespace unima::monitor {

namespace hex_text_detail {
namespace {

constexpr char hex_digits[] = "0123456789ABCDEF";

// "00 " .. "FF ", four bytes a cell so that one load and one store write a byte's text
// (the fourth byte is overwritten by the next cell or lies in the caller's spare byte).
constexpr auto hex_cells = [] {
  std::array<std::array<char, 4>, 256> cells{};
  for (std::size_t b = 0; b < cells.size(); ++b) cells[b] = {hex_digits[b >> 4], hex_digits[b & 0x0F], ' ', ' '};
  return cells;
}();

}  // namespace

char* write_hex_cells_portable(char* out, const std::uint8_t* bytes, std::size_t size) {
  const std::uint8_t* const end = bytes + size;
  for (; end - bytes >= 4; bytes += 4, out += 12) {
    std::memcpy(out, hex_cells[bytes[0]].data(), 4);
    std::memcpy(out + 3, hex_cells[bytes[1]].data(), 4);
    std::memcpy(out + 6, hex_cells[bytes[2]].data(), 4);
    std::memcpy(out + 9, hex_cells[bytes[3]].data(), 4);
  }
  for (; bytes != end; ++bytes, out += 3) std::memcpy(out, hex_cells[*bytes].data(), 4);
  return out;
}

#ifdef UNIMA_HEX_SSSE3
namespace {

// Sixteen bytes make 48 characters, three vectors. Each output vector is picked from the
// digit pairs of bytes 0-7 (`low`) and 8-15 (`high`) by a byte shuffle, and the spaces
// are or-ed in where both shuffles gave zero (an index with its top bit set).
struct ShuffleMasks {
  std::array<std::array<std::uint8_t, 16>, 3> from_low{};
  std::array<std::array<std::uint8_t, 16>, 3> from_high{};
  std::array<std::array<std::uint8_t, 16>, 3> spaces{};
};

constexpr ShuffleMasks shuffle_masks = [] {
  ShuffleMasks m;
  for (std::size_t v = 0; v < 3; ++v) {
    for (std::size_t j = 0; j < 16; ++j) {
      const std::size_t k = 16 * v + j;        // the character's place in the 48
      const std::size_t byte = k / 3, digit = k % 3;  // digit 2 is the space
      m.from_low[v][j] = m.from_high[v][j] = 0x80;
      if (digit == 2) {
        m.spaces[v][j] = ' ';
        continue;
      }
      const std::size_t pair_char = 2 * byte + digit;  // in the 32 characters of digit pairs
      if (pair_char < 16) m.from_low[v][j] = static_cast<std::uint8_t>(pair_char);
      else m.from_high[v][j] = static_cast<std::uint8_t>(pair_char - 16);
    }
  }
  return m;
}();

__attribute__((target("ssse3"))) __m128i load(const std::array<std::uint8_t, 16>& mask) {
  return _mm_loadu_si128(reinterpret_cast<const __m128i*>(mask.data()));
}

}  // namespace

__attribute__((target("ssse3"))) char* write_hex_cells_vector(char* out, const std::uint8_t* bytes,
                                                             std::size_t size) {
  const __m128i digits = _mm_loadu_si128(reinterpret_cast<const __m128i*>(hex_digits));
  const __m128i nibble = _mm_set1_epi8(0x0F);
  __m128i from_low[3], from_high[3], spaces[3];
  for (int v = 0; v < 3; ++v) {
    from_low[v] = load(shuffle_masks.from_low[v]);
    from_high[v] = load(shuffle_masks.from_high[v]);
    spaces[v] = load(shuffle_masks.spaces[v]);
  }
  for (; size >= 16; size -= 16, bytes += 16, out += 48) {
    const __m128i in = _mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes));
    const __m128i high_digits = _mm_shuffle_epi8(digits, _mm_and_si128(_mm_srli_epi16(in, 4), nibble));
    const __m128i low_digits = _mm_shuffle_epi8(digits, _mm_and_si128(in, nibble));
    const __m128i low = _mm_unpacklo_epi8(high_digits, low_digits);   // bytes 0-7: "h l h l ..."
    const __m128i high = _mm_unpackhi_epi8(high_digits, low_digits);  // bytes 8-15
    for (int v = 0; v < 3; ++v) {
      const __m128i text = _mm_or_si128(_mm_or_si128(_mm_shuffle_epi8(low, from_low[v]),
                                                     _mm_shuffle_epi8(high, from_high[v])),
                                        spaces[v]);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 16 * v), text);
    }
  }
  return write_hex_cells_portable(out, bytes, size);
}

bool vector_way_available() {
  static const bool available = __builtin_cpu_supports("ssse3");
  return available;
}
#else
char* write_hex_cells_vector(char* out, const std::uint8_t* bytes, std::size_t size) {
  return write_hex_cells_portable(out, bytes, size);
}
bool vector_way_available() { return false; }
#endif

}  // namespace hex_text_detail

char* write_hex_digits(char* out, std::uint8_t byte) {
  std::memcpy(out, hex_text_detail::hex_cells[byte].data(), 2);
  return out + 2;
}

char* write_hex_cells(char* out, const std::uint8_t* bytes, std::size_t size) {
  // Short runs (function codes, addresses, a CRC) are not worth the masks' loads.
  if (size >= 16 && hex_text_detail::vector_way_available())
    return hex_text_detail::write_hex_cells_vector(out, bytes, size);
  return hex_text_detail::write_hex_cells_portable(out, bytes, size);
}

}  // namespace unima::monitor
