#pragma once
// The master's plan (seed 004 §7.2, SPEC §4): which poll blocks share a request and how
// often each request goes out, and what that costs on the line. Pure.
//
// Poll blocks of one device and function whose registers are consecutive (or overlap, or
// leave a gap of at most `merge_gap` registers) share one request, sent at the shortest of
// their periods. Send blocks are one request each.

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "master/master_value.hpp"
#include "modbus/rtu/rtu_timing.hpp"

namespace unima::master {

/// A poll (MBS_F04 and its extensions) or send (MBS_F06 and its extensions) block, with
/// everything resolved: function, first register or coil, how many, value type.
struct MasterBlock {
  enum class Kind : std::uint8_t { poll, send };
  Kind kind = Kind::poll;
  std::uint8_t device = 1;                 // the foreign slave's Modbus address
  std::uint8_t function = 4;
  std::uint16_t reg = 0;                   // first register or coil, protocol address
  std::uint16_t count = 1;                 // registers, or coils/inputs for bits
  ValueType type = ValueType::word;
  WordOrder order = WordOrder::low_first;
  double scale = 1.0;
  std::chrono::milliseconds period{1000};
  unsigned output = 0;                     // poll: user analog output 1..16
  std::string name;                        // the profile point, or the address in hex
  std::string origin;                      // "file:line:column" of the block

  bool is_read() const { return kind == Kind::poll; }
  bool operator==(const MasterBlock&) const = default;
  std::uint32_t end() const { return std::uint32_t{reg} + count; }
};

struct PlanOptions {
  unsigned merge_gap = 0;                  // registers (or bits) a merged read may skip
  std::uint16_t max_read_registers = 125;  // Modbus Application Protocol V1.1b3 §6.3
  std::uint16_t max_read_bits = 2000;      // §6.1
  bool operator==(const PlanOptions&) const = default;
};

/// One request the master sends every `period`: a merged read, or one write.
struct PlannedRequest {
  std::uint8_t device = 1;
  std::uint8_t function = 4;
  std::uint16_t first = 0;
  std::uint16_t count = 1;                 // registers or bits
  std::chrono::milliseconds period{1000};
  std::chrono::microseconds phase{0};      // the first occurrence, after the start (assign_phases)
  std::vector<std::size_t> blocks;         // indices into the block list, by address
  bool spans_gap = false;                  // reads registers no block asked for

  bool is_read() const;
};

/// Reads merged as described above, then one request per send block; ordered by device,
/// reads before writes, then address.
std::vector<PlannedRequest> plan_requests(std::span<const MasterBlock> blocks, const PlanOptions& options);

/// What to send instead of `request` after the slave answered exception 02 (illegal data
/// address): its gap-free parts when it spans a gap, else one request per block; empty
/// when it is a single block already (the address is wrong, not the merge).
std::vector<PlannedRequest> split_request(const PlannedRequest& request, std::span<const MasterBlock> blocks);

/// Frame sizes on an RTU line (address + PDU + CRC), as the request says and as a normal
/// response to it will be.
std::size_t rtu_request_size(const PlannedRequest& request);
std::size_t rtu_response_size(const PlannedRequest& request);

struct BusLoad {
  double requests_per_second = 0;
  double busy_fraction = 0;  // of the line's time, frames and t3.5 gaps (not the slaves' think time)
};

BusLoad estimate_load(std::span<const PlannedRequest> requests, const modbus::RtuTiming& line);

/// How long a request holds the line: its frames and two t3.5 on RTU; `tcp_slot` on TCP.
std::chrono::microseconds transaction_estimate(const PlannedRequest& request, const std::optional<modbus::RtuTiming>& line,
                                               std::chrono::microseconds tcp_slot = std::chrono::microseconds(1000));

/// Sets each request's phase so that requests which would come due at the same moments
/// are spread apart: by their transaction time on the line, and by the device's minimum
/// gap between requests to one device. Without phases, requests whose periods are
/// multiples of each other all come due together, and each but the first is late by the
/// others' time, period after period. First fit, shortest period first; two requests can
/// only meet at multiples of the greatest common divisor of their periods, so that is the
/// circle their distance is measured on.
void assign_phases(std::vector<PlannedRequest>& requests, std::span<const std::chrono::microseconds> slots,
                   const std::map<std::uint8_t, std::chrono::microseconds>& min_gaps);
/// Requests per second the plan sends to one device.
double device_request_rate(std::span<const PlannedRequest> requests, std::uint8_t device);

}  // namespace unima::master
