#include "io/master/master_rtu_link.hpp"

#include <termios.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "config/master_setup.hpp"
#include "io/modbus/serial_line.hpp"

namespace unima::io {

MasterRtuLink::MasterRtuLink(asio::io_context& io, const config::RtuConfig& line)
    : line_(line),
      timing_(config::line_timing(line)),
      port_(io),
      deadline_(io),
      silence_(io),
      rts_timer_(io),
      reopen_timer_(io) {
  try {
    const auto opened = open_serial_line(port_, line);
    for (const auto& note : opened.notes) spdlog::info("modbus master: {}", note);
    for (const auto& warning : opened.warnings) spdlog::warn("modbus master: {}", warning);
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("modbus master: {}", e.what()));
  }
  if (line.rs485 == config::Rs485Direction::rts) set_rts(false);
}

MasterRtuLink::~MasterRtuLink() { close(); }

std::string MasterRtuLink::describe() const {
  return fmt::format("rtu {} {} 8{}{}", line_.device, line_.baud, parity_letter(line_.parity), line_.stop_bits);
}

master::MasterResponse MasterRtuLink::check(std::span<const std::uint8_t> response, std::uint8_t unit,
                                            std::span<const std::uint8_t> request_pdu) const {
  return master::check_rtu_response(response, unit, request_pdu);
}

void MasterRtuLink::set_rts(bool on) {
  if (!io::set_rts(port_.native_handle(), on) && !rts_warned_) {
    rts_warned_ = true;
    spdlog::warn("modbus master: {}: cannot switch RTS: {}", line_.device, std::strerror(errno));
  }
}

void MasterRtuLink::transact(std::uint8_t unit, const master::Bytes& pdu, std::chrono::milliseconds timeout, Done done) {
  const unsigned generation = ++generation_;
  done_ = std::move(done);
  query_ = master::rtu_frame(unit, pdu);
  response_.clear();
  function_ = pdu[0];
  const auto frame_time = timing_.character * static_cast<long>(query_.size());
  deadline_.expires_after(frame_time + timeout);
  auto self = shared_from_this();
  deadline_.async_wait([this, self, generation](const boost::system::error_code& ec) {
    if (!ec) finish(generation);
  });
  if (!open_) return;  // the device is being reopened: nothing can answer
  // Whatever a slave said after its time-out is not the answer to this request.
  ::tcflush(port_.native_handle(), TCIFLUSH);
  if (line_.rs485 == config::Rs485Direction::rts) set_rts(true);
  asio::async_write(port_, asio::buffer(query_), [this, self, generation, frame_time](const boost::system::error_code& ec,
                                                                                     std::size_t) {
    if (generation != generation_) return;
    if (ec) {
      lost("write failed: " + ec.message());
      return;  // the deadline ends the transaction: no answer
    }
    if (line_.rs485 == config::Rs485Direction::rts) {
      // The last bytes may still be in the UART when the write returns.
      rts_timer_.expires_after(frame_time);
      rts_timer_.async_wait([this, self](const boost::system::error_code& e) {
        if (e) return;  // re-armed by the next frame, or closed
        ::tcdrain(port_.native_handle());
        set_rts(false);
      });
    }
  });
  read(generation);
}

void MasterRtuLink::read(unsigned generation) {
  auto self = shared_from_this();
  port_.async_read_some(asio::buffer(chunk_), [this, self, generation](const boost::system::error_code& ec, std::size_t n) {
    if (generation != generation_ || !done_) return;
    if (ec) {
      if (ec != asio::error::operation_aborted) lost("read failed: " + ec.message());
      return;  // the deadline ends the transaction
    }
    response_.insert(response_.end(), chunk_.begin(), chunk_.begin() + static_cast<std::ptrdiff_t>(n));
    const auto length = master::expected_response_length(response_, function_);
    if (length && response_.size() >= *length) {
      response_.resize(*length);  // what follows is not part of this frame
      return finish(generation);
    }
    // The frame goes on, or has ended without its length being known: a silence decides.
    const auto tolerance = std::max<asio::steady_timer::duration>(timing_.frame_gap, late_byte_tolerance);
    silence_.expires_after(tolerance);
    silence_.async_wait([this, self, generation](const boost::system::error_code& e) {
      if (!e) finish(generation);
    });
    read(generation);
  });
}

void MasterRtuLink::finish(unsigned generation) {
  if (generation != generation_ || !done_) return;
  ++generation_;  // the read, timers and write of this transaction are over
  deadline_.cancel();
  silence_.cancel();
  boost::system::error_code ignored;
  port_.cancel(ignored);
  auto done = std::move(done_);
  done_ = nullptr;
  done(std::move(query_), std::move(response_));
}

void MasterRtuLink::lost(const std::string& why) {
  if (!open_ || closed_) return;
  open_ = false;
  spdlog::warn("modbus master: {} lost: {}; reopening, every {} s at most", line_.device, why,
               config::serial_reopen_longest_delay.count() / 1000);
  boost::system::error_code ignored;
  port_.close(ignored);
  reopen_delay_ = std::chrono::milliseconds(200);
  schedule_reopen();
}

void MasterRtuLink::schedule_reopen() {
  reopen_timer_.expires_after(reopen_delay_);
  reopen_delay_ = std::min(reopen_delay_ * 2, config::serial_reopen_longest_delay);
  reopen_timer_.async_wait([this, self = shared_from_this()](const boost::system::error_code& ec) {
    if (ec || closed_) return;
    try {
      const auto opened = open_serial_line(port_, line_);
      for (const auto& warning : opened.warnings) spdlog::warn("modbus master: {}", warning);
    } catch (const std::exception& e) {
      boost::system::error_code ignored;
      port_.close(ignored);
      spdlog::debug("modbus master: {}", e.what());
      return schedule_reopen();
    }
    if (line_.rs485 == config::Rs485Direction::rts) set_rts(false);
    open_ = true;
    spdlog::info("modbus master: {} back", describe());
    if (reopened_) reopened_();
  });
}

void MasterRtuLink::close() {
  closed_ = true;
  ++generation_;
  done_ = nullptr;
  deadline_.cancel();
  silence_.cancel();
  rts_timer_.cancel();
  reopen_timer_.cancel();
  boost::system::error_code ignored;
  port_.close(ignored);
}

}  // namespace unima::io
