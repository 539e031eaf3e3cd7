#include "modbus/rtu/rtu_framer.hpp"

#include <algorithm>

#include "modbus/protocol.hpp"
#include "modbus/rtu/rtu_adu.hpp"
#include "modbus/rtu/rtu_frame_length.hpp"
#include "modbus/bytes.hpp"

namespace unima::modbus {

namespace {

// An exception response: address, function | 0x80, code, CRC. No answer is shorter.
constexpr std::size_t min_response_size = 5;

}  // namespace

RtuFramerTiming RtuFramerTiming::for_line(const RtuTiming& line, RtuClock::duration adapter_latency) {
  RtuFramerTiming timing;
  timing.character = line.character;
  timing.frame_gap = line.frame_gap;
  timing.stall_timeout = line.frame_gap + adapter_latency + scheduling_margin;
  return timing;
}

RtuFramerTiming RtuFramerTiming::exact(const RtuTiming& line, RtuClock::duration gap) {
  RtuFramerTiming timing;
  timing.character = line.character;
  timing.frame_gap = gap;
  timing.stall_timeout = gap;
  return timing;
}

RtuFramer::RtuFramer(const RtuFramerTiming& timing, std::optional<std::uint8_t> own_address)
    : timing_(timing), own_address_(own_address) {}

void RtuFramer::reset() {
  bytes_.clear();
  arrivals_.clear();
  expected_response_.reset();
  gap_checked_ = false;
}

std::vector<RtuFrame> RtuFramer::feed(std::span<const std::uint8_t> chunk, RtuClock::time_point arrival) {
  std::vector<RtuFrame> out;
  if (chunk.empty()) return out;
  if (!bytes_.empty()) {
    // The read completes after the chunk's last byte; the silence before it was shorter.
    const auto chunk_time = timing_.character * static_cast<long>(chunk.size());
    const auto silence = arrival - arrivals_.back() - chunk_time;
    after_silence(silence, out);
  }
  bytes_.insert(bytes_.end(), chunk.begin(), chunk.end());
  arrivals_.insert(arrivals_.end(), chunk.size(), arrival);
  gap_checked_ = false;
  scan(Mode::streaming, out);
  return out;
}

std::vector<RtuFrame> RtuFramer::tick(RtuClock::time_point now) {
  std::vector<RtuFrame> out;
  if (!bytes_.empty()) after_silence(now - arrivals_.back(), out);
  return out;
}

std::optional<RtuClock::time_point> RtuFramer::deadline() const {
  if (bytes_.empty()) return std::nullopt;
  return arrivals_.back() + (gap_checked_ ? timing_.stall_timeout : timing_.frame_gap);
}

void RtuFramer::after_silence(RtuClock::duration silence, std::vector<RtuFrame>& out) {
  if (silence >= timing_.stall_timeout) {
    scan(Mode::stalled, out);
  } else if (silence >= timing_.frame_gap && !gap_checked_) {
    gap_checked_ = true;
    scan(Mode::after_gap, out);
  }
}

RtuFramer::Attempt RtuFramer::attempt(std::span<const std::uint8_t> held, Hypothesis hypothesis, Mode mode) const {
  RtuFrameLength length;
  RtuFrame::Kind kind = RtuFrame::Kind::query;
  switch (hypothesis) {
    case Hypothesis::query: length = rtu_request_length(held); break;
    case Hypothesis::any_response:
      kind = RtuFrame::Kind::unpaired_response;
      length = rtu_response_length(held);
      break;
    case Hypothesis::expected_response: {
      kind = RtuFrame::Kind::response;
      const auto& e = *expected_response_;
      if (!held.empty() && held[0] != e.address) return {};
      // Seed §5.3 note 3: an answer shorter than the shortest response (5 bytes) that
      // only the silence ended.
      if (mode == Mode::stalled && held.size() >= 2 && held.size() < min_response_size)
        return {Verdict::complete, RtuFrame::Kind::faulty_response, held.size()};
      if (held.size() >= 2 && (held[1] & ~function::exception_flag) != e.function) {
        // The slave answered another function; but a whole request to it is the master
        // moving on (a write's request looks like its response).
        const auto as_request = rtu_request_length(held);
        if (as_request.kind == RtuFrameLength::Kind::known && as_request.bytes <= held.size() &&
            rtu_crc_ok(held.first(as_request.bytes)))
          return {};
        kind = RtuFrame::Kind::faulty_response;
      } else if (held.size() >= 3 && held[1] == e.function && e.byte_count != 0 && held[2] != e.byte_count) {
        return {};
      }
      length = rtu_response_length(held);
      break;
    }
  }
  switch (length.kind) {
    case RtuFrameLength::Kind::impossible: return {};
    case RtuFrameLength::Kind::need_more: return {Verdict::need_more, kind, 0};
    case RtuFrameLength::Kind::known:
      if (length.bytes > held.size()) return {Verdict::need_more, kind, 0};
      return {rtu_crc_ok(held.first(length.bytes)) ? Verdict::complete : Verdict::bad, kind, length.bytes};
    case RtuFrameLength::Kind::unknown:
      // Only a silence ends such a frame; then everything held is the frame.
      if (mode != Mode::streaming && held.size() <= max_rtu_adu_size && rtu_crc_ok(held))
        return {Verdict::complete, kind, held.size()};
      if (mode == Mode::stalled || held.size() > max_rtu_adu_size) return {Verdict::bad, kind, 0};
      return {Verdict::need_more, kind, 0};
  }
  return {};
}

// The expected kind first; a frame it does not fit is tried as the other kinds. The first
// hypothesis that still needs bytes wins over later ones that are complete, so that a
// response is not cut short where its first bytes happen to carry a valid request CRC.
RtuFramer::Attempt RtuFramer::attempt_at(std::size_t at, Mode mode) const {
  const auto held = std::span<const std::uint8_t>(bytes_).subspan(at);
  Hypothesis order[3] = {Hypothesis::query, Hypothesis::any_response, Hypothesis::any_response};
  std::size_t count = 2;
  if (expected_response_) {
    order[0] = Hypothesis::expected_response;
    order[1] = Hypothesis::query;
    count = 3;
  }
  bool bad = false;
  for (std::size_t i = 0; i < count; ++i) {
    const auto a = attempt(held, order[i], mode);
    switch (a.verdict) {
      case Verdict::complete: return a;
      case Verdict::need_more:
        if (mode != Mode::stalled) return a;
        bad = true;  // the silence says it ended: truncated
        break;
      case Verdict::bad: bad = true; break;
      case Verdict::impossible: break;
    }
  }
  return {bad ? Verdict::bad : Verdict::impossible, RtuFrame::Kind::bad, 0};
}

void RtuFramer::scan(Mode mode, std::vector<RtuFrame>& out) {
  while (!bytes_.empty()) {
    const auto a = attempt_at(0, mode);
    if (a.verdict == Verdict::complete) {
      emit(a.kind, a.length, out);
      continue;
    }
    if (a.verdict == Verdict::need_more) return;
    if (a.verdict == Verdict::impossible) {
      ++counters_.skipped_bytes;
      erase_front(1);
      continue;
    }
    // A broken frame at the start: re-synchronise on a valid frame further on.
    std::size_t next = 0;
    for (std::size_t k = 1; k < bytes_.size() && next == 0; ++k)
      if (attempt_at(k, mode).verdict == Verdict::complete) next = k;
    if (next == 0) {
      if (mode == Mode::stalled) {
        next = bytes_.size();
      } else if (bytes_.size() > max_rtu_adu_size) {
        // No frame can be this long: give up the start, keep what may still become one.
        next = 1;
        while (next < bytes_.size() && attempt_at(next, mode).verdict != Verdict::need_more) ++next;
      } else {
        return;  // the next frame may still be arriving
      }
    }
    drop(next, out);
  }
}

void RtuFramer::emit(RtuFrame::Kind kind, std::size_t length, std::vector<RtuFrame>& out) {
  RtuFrame frame;
  frame.kind = kind;
  frame.bytes.assign(bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(length));
  frame.end = arrivals_[length - 1];
  erase_front(length);
  ++counters_.frames;
  expect_after(frame);
  out.push_back(std::move(frame));
}

// Fewer bytes than the shortest frame were never a frame: line noise, skipped.
void RtuFramer::drop(std::size_t length, std::vector<RtuFrame>& out) {
  if (length < min_rtu_adu_size) {
    counters_.skipped_bytes += length;
    erase_front(length);
    return;
  }
  RtuFrame frame;
  frame.kind = RtuFrame::Kind::bad;
  frame.bytes.assign(bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(length));
  frame.end = arrivals_[length - 1];
  erase_front(length);
  ++counters_.bad_frames;
  out.push_back(std::move(frame));
}

void RtuFramer::erase_front(std::size_t length) {
  bytes_.erase(bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(length));
  arrivals_.erase(arrivals_.begin(), arrivals_.begin() + static_cast<std::ptrdiff_t>(length));
}

void RtuFramer::expect_after(const RtuFrame& frame) {
  expected_response_.reset();
  if (frame.kind != RtuFrame::Kind::query) return;
  const std::uint8_t address = frame.bytes[0];
  if (address == broadcast_address || address == own_address_) return;
  Expectation e;
  e.address = address;
  e.function = frame.bytes[1];
  if (frame.bytes.size() == 8) {
    const unsigned quantity = be16(frame.bytes, 4);
    unsigned byte_count = 0;
    if (e.function == function::read_coils || e.function == function::read_discrete_inputs)
      byte_count = (quantity + 7) / 8;
    if (e.function == function::read_holding_registers || e.function == function::read_input_registers)
      byte_count = 2 * quantity;
    // A count a slave must refuse gets an exception, whose length does not depend on it.
    if (byte_count <= max_rtu_adu_size - 5) e.byte_count = static_cast<std::uint16_t>(byte_count);
  }
  expected_response_ = e;
}

}  // namespace unima::modbus
