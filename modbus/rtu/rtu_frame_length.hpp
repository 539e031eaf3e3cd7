#pragma once
// How long an RTU frame is, from its first bytes (Modbus Application Protocol V1.1b3 §6),
// for the functions whose length the frame itself tells: 1–6, 15, 16, 43/14 and every
// exception response. A frame of any other function ends only at a silence.

#include <cstdint>
#include <span>

namespace unima::modbus {

struct RtuFrameLength {
  enum class Kind : std::uint8_t {
    known,       // `bytes` is the whole ADU, CRC included
    need_more,   // the bytes held do not yet tell the length
    unknown,     // a function whose length only the silence after it tells
    impossible,  // no frame of this direction starts like this
  };
  Kind kind = Kind::need_more;
  std::size_t bytes = 0;
};

/// The length of a master's request starting at `held[0]`. Address 0 (broadcast) with a
/// function that reads is impossible: nobody could answer it.
RtuFrameLength rtu_request_length(std::span<const std::uint8_t> held);

/// The length of a slave's response starting at `held[0]`. Address 0 never answers.
RtuFrameLength rtu_response_length(std::span<const std::uint8_t> held);

/// The sizes of a request of `function` for `count` registers or coils (1–6, 15, 16) and
/// of its normal response, before a byte is on the line: for planning the line's time.
std::size_t rtu_request_size(std::uint8_t function, std::uint16_t count);
std::size_t rtu_response_size(std::uint8_t function, std::uint16_t count);

}  // namespace unima::modbus
