#pragma once
// One Modbus transaction as a port saw it: what the monitor logs (SPEC §5, seed §8) and
// what capture blocks and indicators listen to. The bytes are the frames as on the wire.

#include <chrono>
#include <cstdint>
#include <span>
#include <string_view>

namespace unima::modbus {

enum class TransactionState : std::uint8_t {
  done,        // answered normally
  not_for_me,  // a query for another unit/device ("Not4Me"), with its response when heard
  err01,       // exception 01 illegal function
  err02,       // exception 02 illegal data address
  err03,       // exception 03 illegal data value, also bad length or CRC
  err04,       // exception 04, also a foreign response shorter than 5 bytes or with the wrong function
  timeout,     // master: no answer
  cached,      // gateway: a read answered from the cache, without the line (SPEC §14)
};

// tls: Modbus/TCP Security (SPEC §11); gateway: a TCP client's request forwarded on the
// master's line (SPEC §14), the peer the client's address.
enum class PortKind : std::uint8_t { tcp, rtu, master, tls, gateway };

struct Transaction {
  PortKind port = PortKind::tcp;
  std::string_view peer;                  // tcp: "ip:port" of the client; empty otherwise
  std::chrono::system_clock::time_point time;
  TransactionState state = TransactionState::done;
  std::span<const std::uint8_t> query;     // whole ADU: MBAP + PDU, or address + PDU + CRC
  std::span<const std::uint8_t> response;  // whole ADU as sent or heard; empty when none
  /// The response is the bridge's own, sent on its port — not one heard from another
  /// slave, nor none: what lights the Modbus LED in slave mode (SPEC §8).
  bool answered_by_bridge = false;
  /// rtu, master, gateway: the line's name when the bridge has several (SPEC §18: the port
  /// reads `rtu:<name>`); empty with one line, whose names stay `rtu`, `master`, `gw:`.
  std::string_view line{};
};

/// The state a response PDU implies: done, or the Err code of its exception.
inline TransactionState state_of_response(std::span<const std::uint8_t> response_pdu) {
  if (response_pdu.size() >= 2 && (response_pdu[0] & 0x80)) {
    switch (response_pdu[1]) {
      case 0x01: return TransactionState::err01;
      case 0x02: return TransactionState::err02;
      case 0x03: return TransactionState::err03;
      case 0x0A:  // SPEC §14: a unit the gateway does not route
      case 0x0B: return TransactionState::not_for_me;
      default: return TransactionState::err04;
    }
  }
  return TransactionState::done;
}

}  // namespace unima::modbus
