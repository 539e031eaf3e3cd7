#pragma once
// What the bridge as a Modbus slave does with one request, the same on the TCP slave and
// the RTU port (SPEC §3, seed 004 §5): whose request it is by its unit id or address,
// the answer, the state the monitor logs and whether it counts as a fault (C+0x13 bit
// 15). Pure: the ports frame the bytes and send what this says.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "modbus/request_handler.hpp"
#include "modbus/transaction.hpp"

namespace unima::modbus {

enum class Link : std::uint8_t { tcp, rtu };

enum class Recipient : std::uint8_t {
  this_slave,     // answered
  broadcast,      // RTU address 0: writes apply, nothing is answered
  another_slave,  // TCP: answered "gateway target failed"; RTU: Not4Me, silence
};

/// On TCP the own unit id, 0 and 255 are this slave's; on RTU only the own address, and
/// 0 is a broadcast.
Recipient recipient_of(Link link, std::uint8_t address, std::uint8_t own_address);

/// What a TCP or TLS port does with one request (SPEC §3, §11, §14), decided once:
enum class Verdict : std::uint8_t {
  serve,           // serve_request: this slave's; another's that the gateway does not
                   // route is answered there (0x0A behind a gateway, else 0x0B)
  forward,         // to the line of foreign slaves, as it came
  refuse_forward,  // a unit the gateway routes, but this client may not send it this
                   // function (WriteRights::may_forward, the freeze included), or the
                   // gateway forwards reads only (`functions: read`): 01
};

/// `routed_units`: by unit id, what the gateway forwards (nullptr: no gateway).
/// `rights`: the client's (nullptr: everything), as the port's write_rights says.
/// `reads_only`: the gateway forwards functions 1-4 only, whoever asks.
Verdict route(Recipient recipient, std::uint8_t unit, std::uint8_t function,
              const std::array<bool, 256>* routed_units, const WriteRights* rights, bool reads_only = false);

struct Served {
  std::size_t length = 0;  // of the response PDU in `out`; 0: nothing to send
  TransactionState state = TransactionState::done;
  bool fault = false;      // C+0x13 bit 15
  /// What a write in it kept for a restart: the answer waits until that is durable
  /// (io::answer_once_durable), and is refuse_unkept_write's when that fails; 0, answer
  /// at once.
  std::uint64_t kept_as = 0;
};

/// Serves a request PDU (at least its function code) for `recipient` into `out` (at
/// least max_pdu_size bytes). A broadcast never faults: a write to a register the bridge
/// does not have is meant for the other slaves. Another slave's request on RTU is not
/// served (the port listens to it, modbus/rtu/bus_listener).
/// `rights`: what this client may write (nullptr: every register), see handle_request.
/// `gateway`: the bridge forwards some unit ids to its master's line (SPEC §14); another
/// slave's request on TCP that reaches this was not routed: "gateway path unavailable"
/// (0x0A) instead of "gateway target failed" (0x0B).
Served serve_request(Link link, Recipient recipient, std::span<const std::uint8_t> pdu, std::span<std::uint8_t> out,
                     RegisterModel& registers, const HandlerOptions& options, const WriteRights* rights = nullptr,
                     bool gateway = false);

/// What a request served as a write (Served::kept_as) is served as instead when the state
/// file could not keep it and nothing changed (SPEC §10): exception 04 into `out`, Err04
/// and a fault; a broadcast stays unanswered and is no fault, as serve_request says.
/// `function`: the request's function code.
Served refuse_unkept_write(Recipient recipient, std::uint8_t function, std::span<std::uint8_t> out);

/// What a request for a foreign slave behind the gateway is served as when the client may
/// not send it there (WriteRights::may_forward, SPEC §14): exception 01 into `out`, Err01
/// and a fault, as a write to the banks outside the client's rights; nothing goes on the line.
Served refuse_forwarded_write(std::uint8_t function, std::span<std::uint8_t> out);

}  // namespace unima::modbus
