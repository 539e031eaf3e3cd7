#include "io/modbus/rtu_slave_port.hpp"

#include <spdlog/spdlog.h>

#include "io/modbus/serial_line.hpp"
#include "io/state_file.hpp"
#include "modbus/protocol.hpp"
#include "modbus/rtu/rtu_adu.hpp"

namespace unima::io {

using modbus::RtuClock;
using modbus::RtuFrame;
using modbus::TransactionState;

namespace {

std::string hex(std::span<const std::uint8_t> bytes) {
  std::string text;
  for (std::uint8_t b : bytes) text += fmt::format("{}{:02X}", text.empty() ? "" : " ", b);
  return text;
}

}  // namespace

RtuSlavePort::RtuSlavePort(asio::io_context& io, const config::RtuConfig& line, const SlaveContext& context)
    : io_(io),
      line_(line),
      context_(context),
      timing_(config::line_timing(line)),
      framer_(modbus::RtuFramerTiming::for_line(timing_, std::chrono::milliseconds(0)), context.unit_id),
      port_(io),
      silence_(io.get_executor(), [this] { return framer_.deadline(); },
               [this] {
                 handle(framer_.tick(RtuClock::now()));
                 silence_.watch();
               }),
      reply_timer_(io),
      reopen_timer_(io),
      give_up_(io.get_executor(), [this] { return listener_.deadline(); },
               [this] {
                 if (const auto unanswered = listener_.expire(RtuClock::now()))
                   report(TransactionState::not_for_me, unanswered->query, {});
               }) {}

RtuSlavePort::~RtuSlavePort() { stop(); }

void RtuSlavePort::set_context(const SlaveContext& context) {
  context_ = context;
  framer_.set_own_address(context.unit_id);
}

void RtuSlavePort::start() {
  running_ = true;
  open();
}

void RtuSlavePort::stop() {
  if (!running_) return;
  running_ = false;
  reopen_timer_.cancel();
  close();
}

void RtuSlavePort::open() {
  OpenedLine opened;
  try {
    opened = open_serial_line(port_, line_);
  } catch (const std::exception& e) {
    boost::system::error_code ignored;
    port_.close(ignored);
    if (!failing_)
      spdlog::error("modbus rtu: {}; retrying, every {} s at most", e.what(), longest_reopen_delay.count() / 1000);
    else
      spdlog::debug("modbus rtu: {}", e.what());
    failing_ = true;
    schedule_reopen();
    return;
  }
  for (const auto& note : opened.notes) spdlog::info("modbus rtu: {}", note);
  for (const auto& warning : opened.warnings) spdlog::warn("modbus rtu: {}", warning);
  // The framer must not take the adapter's pauses for the end of a frame, unless the
  // line's gap is set exactly (a real UART).
  framer_ = modbus::RtuFramer(line_.frame_gap ? modbus::RtuFramerTiming::exact(timing_, *line_.frame_gap)
                                              : modbus::RtuFramerTiming::for_line(timing_, opened.adapter_latency),
                              context_.unit_id);
  spdlog::info("modbus rtu: {}serving unit {} on {} at {} baud, 8{}{}", failing_ ? "line back, " : "",
               context_.unit_id, line_.device, line_.baud, parity_letter(line_.parity), line_.stop_bits);
  failing_ = false;
  read();
}

void RtuSlavePort::schedule_reopen() {
  if (!running_) return;
  reopen_timer_.expires_after(reopen_delay_);
  reopen_delay_ = std::min(reopen_delay_ * 2, longest_reopen_delay);
  reopen_timer_.async_wait([this, g = guard()](const boost::system::error_code& ec) {
    if (ec || !HandlerGuard::alive(g) || !guard_.current(g) || !running_) return;
    open();
  });
}

void RtuSlavePort::lost(const std::string& why) {
  spdlog::warn("modbus rtu: {} lost: {}; reopening", line_.device, why);
  flush_foreign_query();
  close();
  failing_ = true;
  schedule_reopen();
}

void RtuSlavePort::close() {
  guard_.invalidate();
  boost::system::error_code ignored;
  if (port_.is_open()) {
    if (line_.rs485 == config::Rs485Direction::rts) set_rts(port_.native_handle(), false);
    port_.close(ignored);
  }
  silence_.cancel();
  reply_timer_.cancel();
  sending_ = false;
  out_.clear();
  (void)listener_.interrupted();  // a line lost mid-exchange logs nothing more of it
  give_up_.cancel();
  framer_.reset();
}

void RtuSlavePort::read() {
  port_.async_read_some(asio::buffer(in_), [this, g = guard()](const boost::system::error_code& ec, std::size_t n) {
    if (!HandlerGuard::alive(g) || !guard_.current(g) || ec == asio::error::operation_aborted) return;
    if (ec) return lost(ec == asio::error::eof ? "end of file" : ec.message());
    // Only a line that delivers bytes has come back for good: one that opens and fails
    // at once keeps its back-off growing.
    reopen_delay_ = first_reopen_delay;
    handle(framer_.feed(std::span<const std::uint8_t>(in_.data(), n), RtuClock::now()));
    // New bytes only move the framer's deadline later: one timer, armed when none is.
    silence_.watch();
    read();
  });
}

void RtuSlavePort::handle(const std::vector<RtuFrame>& frames) {
  for (const auto& frame : frames) {
    ++(frame.kind == RtuFrame::Kind::bad || frame.kind == RtuFrame::Kind::faulty_response ? counters_.errors
                                                                                           : counters_.frames_received);
    switch (frame.kind) {
      case RtuFrame::Kind::query: {
        flush_foreign_query();
        switch (modbus::recipient_of(modbus::Link::rtu, frame.bytes[0], context_.unit_id)) {
          case modbus::Recipient::this_slave: answer(frame); break;
          case modbus::Recipient::broadcast: apply_broadcast(frame); break;
          case modbus::Recipient::another_slave: heard_foreign_query(frame); break;
        }
        break;
      }
      case RtuFrame::Kind::response: heard_foreign_response(frame); break;
      case RtuFrame::Kind::faulty_response: heard_faulty_response(frame); break;
      case RtuFrame::Kind::unpaired_response:
        spdlog::debug("modbus rtu: a response to no query heard: {}", hex(frame.bytes));
        break;
      case RtuFrame::Kind::bad:
        // Seed §5.3: Err03 also for a bad length or CRC. No reply: the address is not sure.
        flush_foreign_query();
        spdlog::debug("modbus rtu: bad frame dropped: {}", hex(frame.bytes));
        if (context_.on_fault) context_.on_fault();
        report(TransactionState::err03, frame.bytes, {});
        break;
    }
  }
}

modbus::Served RtuSlavePort::serve(const RtuFrame& query, modbus::Recipient recipient,
                                   std::span<std::uint8_t> response) const {
  const auto pdu = std::span<const std::uint8_t>(query.bytes).subspan(1, query.bytes.size() - 3);
  return modbus::serve_request(modbus::Link::rtu, recipient, pdu, response, *context_.registers, context_.options);
}

void RtuSlavePort::answer(const RtuFrame& query) {
  std::array<std::uint8_t, modbus::max_pdu_size> response{};
  const auto served = serve(query, modbus::Recipient::this_slave, response);
  const auto not_before = query.end + timing_.reply_delay;
  if (served.kept_as == 0) return reply(query.bytes, served, response, not_before);
  // A write takes effect and is answered once the state file holds it; one the file could
  // not take changed nothing and is answered exception 04 (SPEC §10).
  answer_once_durable(context_.state, served.kept_as,
                      [this, g = guard(), query = query.bytes, served, response, not_before](bool durable) mutable {
                        if (!HandlerGuard::alive(g) || !guard_.current(g)) return;
                        const auto sent =
                            durable ? served : modbus::refuse_unkept_write(modbus::Recipient::this_slave, query[1], response);
                        reply(query, sent, response, not_before);
                      });
}

void RtuSlavePort::reply(std::span<const std::uint8_t> query, const modbus::Served& served,
                         std::span<const std::uint8_t> response, RtuClock::time_point not_before) {
  std::vector<std::uint8_t> adu(served.length + 3);
  modbus::write_rtu_adu(query[0], response.first(served.length), adu);
  if (served.fault && context_.on_fault) context_.on_fault();
  report(served.state, query, adu, true);
  send(std::move(adu), not_before);
}

// Writes apply once the state file holds them, nothing is answered (SPEC §3); the capture
// blocks hear it at once, as the other slaves on the line did.
void RtuSlavePort::apply_broadcast(const RtuFrame& query) {
  std::array<std::uint8_t, modbus::max_pdu_size> response{};
  const auto served = serve(query, modbus::Recipient::broadcast, response);
  answer_once_durable(context_.state, served.kept_as, [this, g = guard(), query = query.bytes, served](bool durable) {
    if (!HandlerGuard::alive(g)) return;
    std::array<std::uint8_t, modbus::max_pdu_size> refusal{};
    const auto state =
        durable ? served.state : modbus::refuse_unkept_write(modbus::Recipient::broadcast, query[1], refusal).state;
    report(state, query, {});
  });
  if (foreign_) foreign_(query.bytes, {});
}

void RtuSlavePort::heard_foreign_query(const RtuFrame& query) {
  listener_.heard_query(query.bytes, query.end);
  give_up_.watch();
  if (foreign_) foreign_(query.bytes, {});
}

void RtuSlavePort::heard_foreign_response(const RtuFrame& response) {
  const auto exchange = listener_.heard_response(response.bytes);
  if (!exchange) {
    spdlog::debug("modbus rtu: a response after its query was given up: {}", hex(response.bytes));
    return;
  }
  report(TransactionState::not_for_me, exchange->query, exchange->response);
  if (foreign_) foreign_(exchange->query, exchange->response);
}

// Seed §5.3 note 3: a foreign slave's answer that is too short or of another function is
// Err04 on its query's line, and a fault (C+0x13 bit 15); capture blocks take nothing of it.
void RtuSlavePort::heard_faulty_response(const RtuFrame& response) {
  const auto exchange = listener_.heard_response(response.bytes);
  if (!exchange) {
    spdlog::debug("modbus rtu: a faulty response after its query was given up: {}", hex(response.bytes));
    return;
  }
  if (context_.on_fault) context_.on_fault();
  report(TransactionState::err04, exchange->query, exchange->response);
}

void RtuSlavePort::flush_foreign_query() {
  if (const auto unanswered = listener_.interrupted()) report(TransactionState::not_for_me, unanswered->query, {});
}

void RtuSlavePort::report(TransactionState state, std::span<const std::uint8_t> query,
                          std::span<const std::uint8_t> response, bool ours) const {
  if (!context_.on_transaction) return;
  context_.on_transaction(
      modbus::Transaction{modbus::PortKind::rtu, {}, std::chrono::system_clock::now(), state, query, response, ours});
}

void RtuSlavePort::send(std::vector<std::uint8_t> adu, RtuClock::time_point not_before) {
  out_.push_back({std::move(adu), not_before});
  if (!sending_) write_next();
}

// The reply timer is armed only when the 2.5 characters after the request have not yet
// passed (behind a USB adapter they usually have).
void RtuSlavePort::write_next() {
  if (out_.empty() || !port_.is_open()) return;
  sending_ = true;
  const auto& next = out_.front();
  if (RtuClock::now() < next.not_before) {
    reply_timer_.expires_at(next.not_before);
    reply_timer_.async_wait([this, g = guard()](const boost::system::error_code& ec) {
      if (ec || !HandlerGuard::alive(g) || !guard_.current(g)) return;
      if (!out_.empty()) out_.front().not_before = RtuClock::time_point::min();
      write_next();
    });
    return;
  }
  if (line_.rs485 == config::Rs485Direction::rts) set_rts(port_.native_handle(), true);
  asio::async_write(port_, asio::buffer(next.bytes),
                    [this, g = guard()](const boost::system::error_code& ec, std::size_t) {
                      if (!HandlerGuard::alive(g) || !guard_.current(g) || ec == asio::error::operation_aborted) return;
                      if (ec) return lost(ec.message());
                      ++counters_.frames_sent;
                      if (line_.rs485 == config::Rs485Direction::rts) return release_line_after_sending();
                      out_.pop_front();
                      sending_ = false;
                      write_next();
                    });
}

// With RTS direction control the driver must stay enabled until the last stop bit has
// left the UART, which is later than the write's completion: wait for the bytes still
// queued, then for the shift register, a character at a time.
void RtuSlavePort::release_line_after_sending() {
  const int fd = port_.native_handle();
  const auto empty = transmitter_empty(fd);
  if (empty.value_or(true) && output_queue(fd).value_or(0) == 0) {
    set_rts(fd, false);
    out_.pop_front();
    sending_ = false;
    write_next();
    return;
  }
  const auto queued = std::max(output_queue(fd).value_or(0), 0);
  reply_timer_.expires_after(timing_.character * (queued + 1));
  reply_timer_.async_wait([this, g = guard()](const boost::system::error_code& ec) {
    if (ec || !HandlerGuard::alive(g) || !guard_.current(g)) return;
    release_line_after_sending();
  });
}

}  // namespace unima::io
