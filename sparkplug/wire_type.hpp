#pragma once
// Protobuf's wire types (its "Encoding" guide), for the encoder and the decoder of
// Sparkplug's payload alike; 6 and 7 are undefined.

#include <cstdint>

namespace unima::sparkplug {

enum class WireType : std::uint8_t { varint = 0, fixed64 = 1, length_delimited = 2, start_group = 3, end_group = 4, fixed32 = 5 };

}  // namespace unima::sparkplug
