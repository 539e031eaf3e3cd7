#pragma once
// The parts of a Modbus ADU as it was seen on the wire, for the monitor, its filter and
// the capture indicators. Unlike parse_tcp_adu it never refuses a frame: a short or
// malformed frame still shows whatever parts it has (seed 004 §8 shows faulty frames too).

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "modbus/mbap.hpp"
#include "modbus/transaction.hpp"

namespace unima::modbus {

enum class Framing : std::uint8_t {
  tcp,  // MBAP header + PDU
  rtu,  // address + PDU + CRC (low byte first)
};

/// How a port's frames are built: tcp -> MBAP, rtu -> RTU; a master on the serial line
/// speaks RTU, a master with a TCP target (Transaction::peer set) speaks MBAP.
Framing framing_of(const Transaction& transaction);

struct AduView {
  std::optional<MbapHeader> mbap;           // tcp, when the frame holds the whole header
  std::optional<std::uint8_t> address;      // unit id (tcp) or slave address (rtu)
  std::span<const std::uint8_t> pdu;        // function code and data; empty when none
  std::optional<std::uint16_t> crc_on_wire; // rtu: first wire byte in the high half ("21CE")
};

/// Splits `frame` without validating it: a tcp frame shorter than the header has no
/// mbap and no PDU; an rtu frame shorter than 3 bytes has no CRC.
AduView view_adu(std::span<const std::uint8_t> frame, Framing framing);

/// The frame `view` was taken from, byte for byte (view_adu's inverse, for a frame read
/// back from the monitor log): MBAP header + PDU, or address + PDU + CRC as far as the
/// frame had them. Empty when the view holds no bytes of it (a TCP frame shorter than its
/// header: the monitor keeps only its size).
std::vector<std::uint8_t> adu_bytes(const AduView& view);

}  // namespace unima::modbus
