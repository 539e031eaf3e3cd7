#pragma once
// Cuts the bytes of a Modbus RTU line into frames (Modbus over Serial Line V1.02
// §2.5.1.1, SPEC §3). Pure: it is fed chunks with their arrival times and told how long
// the line has been silent; it never reads a clock and owns no port.
//
// A frame ends as soon as its length says it is complete (functions 1–6, 15, 16, 43/14
// and exceptions), or at t3.5 of silence when its function does not tell its length. A
// USB adapter delivers bytes in bursts up to its latency timer apart, so a frame whose
// length is known but not reached yet waits for the stall time-out (t3.5 + adapter
// latency + a margin) before it is dropped as truncated. After a bad CRC the framer looks
// for a valid frame in what it holds and re-synchronises there.
//
// A request and a response can look alike, so the framer keeps a small state: after a
// request for another address it expects that slave's response (same address, same
// function or its exception, the byte count the request asked for), otherwise a request.
// A frame that does not fit the expectation is tried as the other kind before it counts
// as bad. The frame after such a query from the slave it asked is its response even when
// it is not a valid one: shorter than 5 bytes (ended by the stall time-out) or with another
// function — unless it is also a whole request, as a master's next write to that slave
// would be (a write's request and response look alike). What stays ambiguous: a write
// (5, 6) to a slave that never answers, followed by the same write again, pairs the
// repeat as the response.

#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "modbus/rtu/rtu_timing.hpp"

namespace unima::modbus {

using RtuClock = std::chrono::steady_clock;

struct RtuFrame {
  enum class Kind : std::uint8_t {
    query,              // a master's request
    response,           // the answer to the query just before it
    faulty_response,    // from the slave the query before it asked, but not a valid answer to
                        // it: shorter than 5 bytes, or with another function (seed §5.3 note 3)
    unpaired_response,  // shaped like an answer, but not to the query before it
    bad,                // a bad CRC or a truncated frame, dropped
  };
  Kind kind = Kind::bad;
  std::vector<std::uint8_t> bytes;  // the whole ADU as on the wire, CRC included
  RtuClock::time_point end;         // arrival of its last byte
};

struct RtuFramerTiming {
  RtuClock::duration character{};      // a chunk of n bytes took n characters to arrive
  RtuClock::duration frame_gap{};      // t3.5
  RtuClock::duration stall_timeout{};  // silence after which an incomplete frame is dropped

  /// Bytes can be held back by a USB adapter (its latency timer) and by the scheduling
  /// of the reading process: a few milliseconds that no line timing accounts for.
  static constexpr std::chrono::milliseconds scheduling_margin{5};
  /// `frame_gap: auto`: an incomplete frame is dropped after t3.5 + the adapter's latency +
  /// scheduling_margin of silence, so that bursts of a USB adapter are joined.
  static RtuFramerTiming for_line(const RtuTiming& line, RtuClock::duration adapter_latency);
  /// `frame_gap: <duration>`: the Modbus rule on a real UART; `gap` (at least t3.5) of
  /// silence ends or breaks any frame.
  static RtuFramerTiming exact(const RtuTiming& line, RtuClock::duration gap);
};

class RtuFramer {
 public:
  struct Counters {
    std::uint64_t frames = 0;         // good frames of any kind
    std::uint64_t bad_frames = 0;     // bad CRC or truncated
    std::uint64_t skipped_bytes = 0;  // bytes that could not start a frame
  };

  /// `own_address`: requests for it are answered by the caller, so after one the line
  /// carries a request again. Without it (a pure listener) every addressed request is
  /// expected to be answered.
  RtuFramer(const RtuFramerTiming& timing, std::optional<std::uint8_t> own_address);

  /// Bytes that arrived at `arrival` (the time their read completed).
  std::vector<RtuFrame> feed(std::span<const std::uint8_t> chunk, RtuClock::time_point arrival);
  /// Nothing arrived until `now`: frames that the silence completes or breaks.
  std::vector<RtuFrame> tick(RtuClock::time_point now);
  /// When tick() may next have something to say; nullopt when nothing is held.
  std::optional<RtuClock::time_point> deadline() const;

  /// Forgets what it holds and expects a request (the port was reopened).
  void reset();
  void set_own_address(std::optional<std::uint8_t> own_address) { own_address_ = own_address; }
  const Counters& counters() const { return counters_; }
  std::size_t held() const { return bytes_.size(); }

 private:
  enum class Mode : std::uint8_t { streaming, after_gap, stalled };
  enum class Verdict : std::uint8_t { complete, need_more, bad, impossible };
  enum class Hypothesis : std::uint8_t { expected_response, query, any_response };
  struct Attempt {
    Verdict verdict = Verdict::impossible;
    RtuFrame::Kind kind = RtuFrame::Kind::bad;
    std::size_t length = 0;
  };
  struct Expectation {
    std::uint8_t address = 0;
    std::uint8_t function = 0;
    std::uint16_t byte_count = 0;  // of a read's response; 0 when the request does not tell
  };

  Attempt attempt(std::span<const std::uint8_t> held, Hypothesis hypothesis, Mode mode) const;
  Attempt attempt_at(std::size_t at, Mode mode) const;
  void after_silence(RtuClock::duration silence, std::vector<RtuFrame>& out);
  void scan(Mode mode, std::vector<RtuFrame>& out);
  void emit(RtuFrame::Kind kind, std::size_t length, std::vector<RtuFrame>& out);
  void drop(std::size_t length, std::vector<RtuFrame>& out);
  void erase_front(std::size_t length);
  void expect_after(const RtuFrame& frame);

  RtuFramerTiming timing_;
  std::optional<std::uint8_t> own_address_;
  std::optional<Expectation> expected_response_;
  std::vector<std::uint8_t> bytes_;
  std::vector<RtuClock::time_point> arrivals_;  // per byte held
  bool gap_checked_ = false;
  Counters counters_;
};

}  // namespace unima::modbus
