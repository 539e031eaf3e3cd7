#pragma once
// One monitor line per transaction (SPEC §5, seed 004 §8), in text or as a JSON line, and
// the reading of such a line back (for `unima-bridge monitor`). Pure: no clock, no I/O.
//
// Text, fields in this order, hex bytes upper case and space separated:
//   <UTC ISO-8601 with µs> <port> Ix=<0..255> Rc=<bytes> State=<state>
//       [TrID=xxxx PtID=xxxx Len=xxxx] Ad=<dec> PDU=<hex bytes> [CRC=xxxx] Response=<hex bytes | ->
// TrID/PtID/Len are there for MBAP frames, CRC for RTU frames; a part the frame is too
// short to hold reads "-". When the monitor had to drop transactions it says so:
//   <time> monitor Dropped=<n>
// JSON lines carry the same fields: {"time","port","ix","rc","state","trid","ptid","len",
// "ad","pdu","crc","response"} (numbers for ix, rc, trid, ptid, len, ad; hex strings for
// bytes and the CRC; null for "-"), and {"time","port":"monitor","dropped":n}.

#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "modbus/adu_view.hpp"
#include "modbus/transaction.hpp"
#include "monitor/monitor_config.hpp"

namespace unima::monitor {

/// "Done", "Not4Me", "Err01".."Err04", "Timeout", "Cached".
std::string_view state_name(modbus::TransactionState state);
std::optional<modbus::TransactionState> parse_state(std::string_view name);

/// "tcp:<peer ip>:<peer port>", "rtu" or "master" (SPEC §5); with a line's name (SPEC §18)
/// "rtu:<line>", "master:<line>", "gw:<line>:<peer>".
void append_port_name(std::string& out, modbus::PortKind port, std::string_view peer, std::string_view line = {});

/// Everything a line says, as views into the transaction's bytes.
struct MonitorFields {
  std::chrono::system_clock::time_point time;
  std::string_view port;
  std::uint8_t ix = 0;
  std::size_t rc = 0;  // query bytes as on the wire
  modbus::TransactionState state = modbus::TransactionState::done;
  modbus::AduView query;
  std::span<const std::uint8_t> response;  // empty: none sent or heard ("-")
};

/// `port_name` must outlive the result (see append_port_name).
MonitorFields monitor_fields(const modbus::Transaction& transaction, std::uint8_t ix, std::string_view port_name);

/// Appends the line and its "\n".
void append_monitor_line(std::string& out, const MonitorFields& fields, MonitorFormat format);
void append_drop_notice(std::string& out, std::chrono::system_clock::time_point time, std::uint64_t dropped,
                        MonitorFormat format);
/// The most bytes the line of `fields` can take, in either format.
std::size_t monitor_line_bound(const MonitorFields& fields);
/// The same line written into `out`, which has room for monitor_line_bound(fields) bytes
/// (no string to grow: the monitor's writer formats straight into its write buffer).
/// Returns the end of what was written.
char* write_monitor_line(char* out, const MonitorFields& fields, MonitorFormat format);

/// A line read back; owns its bytes.
struct MonitorLine {
  enum class Kind : std::uint8_t { transaction, drop_notice };
  Kind kind = Kind::transaction;
  std::chrono::system_clock::time_point time;
  std::string port;
  std::uint8_t ix = 0;
  std::size_t rc = 0;
  modbus::TransactionState state = modbus::TransactionState::done;
  std::optional<modbus::MbapHeader> mbap;
  std::optional<std::uint8_t> address;
  std::vector<std::uint8_t> pdu;
  std::optional<std::uint16_t> crc_on_wire;
  std::vector<std::uint8_t> response;
  std::uint64_t dropped = 0;  // drop notices

  /// Views into this line, for formatting it again or filtering it.
  MonitorFields fields() const;
};

/// Reads a text or JSON line (either may end in "\n"); nullopt when it is neither.
std::optional<MonitorLine> parse_monitor_line(std::string_view line);

}  // namespace unima::monitor
