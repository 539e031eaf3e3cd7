// Fuzz target: what arrives on an RS-485 line, down the RTU port's path
// (io/modbus/rtu_slave_port): modbus::RtuFramer cuts the bytes by length and silence, the
// queries for the bridge are served against the banks of config/examples/four-devices.yaml,
// another slave's query and its response are paired (modbus::BusListener) and read by the
// capture blocks and the monitor's capture rule.
//
// Input: byte 0 sets up the line (baud, parity, `frame_gap: auto` with an adapter latency or
// an exact gap, the bridge's address, the extensions); then chunks as a read delivers them:
//   [n] [silence] n bytes   (n = 0: no bytes, the silence timer fires)
// where the silence before the chunk's first byte is in units of 100 µs. Times are
// synthetic and only move forward; at the end the line falls silent for good.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "fuzz/bridge_banks.hpp"
#include "fuzz/fuzz_check.hpp"
#include "modbus/rtu/bus_listener.hpp"
#include "modbus/capture.hpp"
#include "modbus/register_capture.hpp"
#include "modbus/rtu/rtu_adu.hpp"
#include "modbus/rtu/rtu_framer.hpp"
#include "modbus/slave_session.hpp"

namespace {

using namespace unima;
using modbus::RtuClock;
using modbus::RtuFrame;
using namespace std::chrono_literals;

// Capture blocks on foreign slaves 2 and 3 (SPEC §4): registers a seed frame touches.
const modbus::CaptureRule capture_rules[] = {{2, 0x0011, 1}, {2, 0x0101, 2}, {3, 0x0000, 3}, {3, 0x0009, 4}};

struct Line {
  modbus::RtuFramerTiming timing;
  std::uint8_t own_address = 1;
  modbus::HandlerOptions options;
};

Line line_of(std::uint8_t setup) {
  static constexpr unsigned bauds[] = {4800, 9600, 19200, 115200};
  Line line;
  const auto rtu = modbus::rtu_timing(bauds[setup & 0x03], (setup & 0x04) != 0, 1);
  static constexpr RtuClock::duration latencies[] = {0ms, 1ms, 16ms};
  if (setup & 0x08) line.timing = modbus::RtuFramerTiming::exact(rtu, std::max<RtuClock::duration>(rtu.frame_gap, 2ms));
  else line.timing = modbus::RtuFramerTiming::for_line(rtu, latencies[(setup >> 4) % 3]);
  line.own_address = (setup & 0x40) ? 2 : 1;
  line.options.max_read_registers = modbus::max_read_registers_rtu;
  line.options.device_identification = !(setup & 0x80);
  return line;
}

class Port {
 public:
  Port(const Line& line, fuzz::BridgeBanks& banks) : line_(line), banks_(banks) {}

  void handle(const std::vector<RtuFrame>& frames, RtuClock::time_point until) {
    for (const auto& frame : frames) {
      check_frame(frame, until);
      ++(frame.kind == RtuFrame::Kind::bad ? bad_frames_ : frames_);
      framed_bytes_ += frame.bytes.size();
      switch (frame.kind) {
        case RtuFrame::Kind::query: query(frame); break;
        case RtuFrame::Kind::response:
        case RtuFrame::Kind::faulty_response:
          if (const auto exchange = listener_.heard_response(frame.bytes); exchange && frame.kind == RtuFrame::Kind::response)
            heard(exchange->query, exchange->response);
          break;
        case RtuFrame::Kind::unpaired_response: break;
        case RtuFrame::Kind::bad: (void)listener_.interrupted(); break;
      }
    }
  }

  std::size_t frames() const { return frames_; }
  std::size_t bad_frames() const { return bad_frames_; }
  std::size_t framed_bytes() const { return framed_bytes_; }

 private:
  void check_frame(const RtuFrame& frame, RtuClock::time_point until) {
    FUZZ_CHECK(frame.end <= until && frame.end >= last_end_);
    last_end_ = frame.end;
    const auto& bytes = frame.bytes;
    switch (frame.kind) {
      case RtuFrame::Kind::query:
        FUZZ_CHECK(bytes.size() >= modbus::min_rtu_adu_size && bytes.size() <= modbus::max_rtu_adu_size);
        FUZZ_CHECK(modbus::rtu_crc_ok(bytes) && !(bytes[1] & modbus::function::exception_flag));
        break;
      case RtuFrame::Kind::response:
      case RtuFrame::Kind::unpaired_response:
        FUZZ_CHECK(bytes.size() >= 5 && bytes.size() <= modbus::max_rtu_adu_size && modbus::rtu_crc_ok(bytes));
        FUZZ_CHECK(bytes[0] != modbus::broadcast_address);  // address 0 never answers
        break;
      case RtuFrame::Kind::faulty_response:
        FUZZ_CHECK(bytes.size() >= 2 && bytes.size() <= modbus::max_rtu_adu_size);
        break;
      case RtuFrame::Kind::bad: FUZZ_CHECK(bytes.size() >= modbus::min_rtu_adu_size); break;
    }
  }

  void query(const RtuFrame& frame) {
    (void)listener_.interrupted();  // a query unanswered before this one
    const auto pdu = std::span<const std::uint8_t>(frame.bytes).subspan(1, frame.bytes.size() - 3);
    // Exactly the answer's room: ASan sees any byte written past it.
    std::vector<std::uint8_t> response(modbus::max_pdu_size);
    switch (const auto recipient = modbus::recipient_of(modbus::Link::rtu, frame.bytes[0], line_.own_address)) {
      case modbus::Recipient::this_slave: {
        const auto served = modbus::serve_request(modbus::Link::rtu, recipient, pdu, response, banks_.model, line_.options);
        FUZZ_CHECK(served.length >= 2 && served.length <= modbus::max_pdu_size);
        FUZZ_CHECK(served.state == modbus::state_of_response(std::span(response).first(served.length)));
        std::vector<std::uint8_t> adu(served.length + 3);
        modbus::write_rtu_adu(frame.bytes[0], std::span(response).first(served.length), adu);
        FUZZ_CHECK(adu.size() <= modbus::max_rtu_adu_size && modbus::rtu_crc_ok(adu));  // seed §5.1: ≤ 256 bytes
        break;
      }
      case modbus::Recipient::broadcast: {
        const auto served = modbus::serve_request(modbus::Link::rtu, recipient, pdu, response, banks_.model, line_.options);
        FUZZ_CHECK(served.length == 0 && !served.fault);  // a broadcast is never answered
        heard(frame.bytes, {});
        break;
      }
      case modbus::Recipient::another_slave: {
        const auto served = modbus::serve_request(modbus::Link::rtu, recipient, pdu, response, banks_.model, line_.options);
        FUZZ_CHECK(served.length == 0 && served.state == modbus::TransactionState::not_for_me);  // Not4Me: silence
        listener_.heard_query(frame.bytes, frame.end);
        heard(frame.bytes, {});
        break;
      }
    }
  }

  // What the capture blocks and the monitor's indicators take of an exchange on the line.
  void heard(std::span<const std::uint8_t> query, std::span<const std::uint8_t> response) {
    const auto taken = response.empty() ? modbus::captured_writes(capture_rules, query)
                                        : modbus::captured_reads(capture_rules, query, response);
    FUZZ_CHECK(taken.size() <= std::size(capture_rules));
    const modbus::Transaction transaction{modbus::PortKind::rtu, {}, {}, modbus::TransactionState::not_for_me, query, response};
    if (const auto captured = modbus::captured_registers(transaction))
      FUZZ_CHECK(captured->count() >= 1 && captured->count() <= 127 && captured->data.size() % 2 == 0);
  }

  const Line& line_;
  fuzz::BridgeBanks& banks_;
  modbus::BusListener listener_{100ms};
  RtuClock::time_point last_end_{};
  std::size_t frames_ = 0;
  std::size_t bad_frames_ = 0;
  std::size_t framed_bytes_ = 0;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const Line line = line_of(data[0]);
  fuzz::BridgeBanks banks(fuzz::example("four-devices.yaml"));
  banks.bring_plant_online();
  Port port(line, banks);
  modbus::RtuFramer framer(line.timing, line.own_address);

  RtuClock::time_point now{};
  std::size_t fed = 0;
  std::size_t at = 1;
  while (at + 2 <= size) {
    const std::size_t n = data[at];
    const auto silence = std::chrono::microseconds(100) * data[at + 1];
    at += 2;
    if (n == 0) {
      now += silence;
      port.handle(framer.tick(now), now);
    } else {
      const auto chunk = std::span(data + at, std::min(n, size - at));
      if (chunk.empty()) break;  // a read delivers at least one byte
      at += chunk.size();
      // The read completes when the chunk's last byte has arrived.
      now += silence + line.timing.character * static_cast<long>(chunk.size());
      port.handle(framer.feed(chunk, now), now);
      fed += chunk.size();
    }
    // Whatever is held has a deadline still to come, when the port's timer calls tick().
    FUZZ_CHECK(framer.deadline().has_value() == (framer.held() > 0));
    if (const auto deadline = framer.deadline()) FUZZ_CHECK(*deadline > now);
  }
  // The line falls silent: whatever is held ends as a frame or is dropped.
  now += line.timing.stall_timeout;
  port.handle(framer.tick(now), now);
  FUZZ_CHECK(framer.held() == 0 && !framer.deadline());

  // Every byte fed is in a frame or counted as skipped, once.
  const auto& counters = framer.counters();
  FUZZ_CHECK(counters.frames == port.frames() && counters.bad_frames == port.bad_frames());
  FUZZ_CHECK(port.framed_bytes() + counters.skipped_bytes == fed);
  return 0;
}
