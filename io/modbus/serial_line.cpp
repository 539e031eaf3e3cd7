#include "io/modbus/serial_line.hpp"

#include <linux/serial.h>
#include <sys/ioctl.h>

#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

#include "io/modbus/usb_latency.hpp"

namespace unima::io {

namespace {

using Port = asio::serial_port;

void set_or_throw(const std::string& device, const char* what, boost::system::error_code ec) {
  if (ec) throw std::runtime_error(fmt::format("{}: cannot set {}: {}", device, what, ec.message()));
}

void set_baud(Port& port, const config::RtuConfig& line) {
  boost::system::error_code ec;
  port.set_option(Port::baud_rate(line.baud), ec);
  if (ec == boost::asio::error::invalid_argument) {
    // No Bxxxx constant for this rate (14400, a rate of the seed).
    const int error = set_custom_baud(port.native_handle(), line.baud);
    if (error == 0) return;
    ec = boost::system::error_code(error, boost::system::system_category());
  }
  set_or_throw(line.device, fmt::format("{} baud", line.baud).c_str(), ec);
}

Port::parity::type parity_of(config::Parity parity) {
  switch (parity) {
    case config::Parity::even: return Port::parity::even;
    case config::Parity::odd: return Port::parity::odd;
    case config::Parity::none: break;
  }
  return Port::parity::none;
}

// The kernel switches the driver enable itself: RTS up while sending, down after, and
// the receiver deaf to our own transmission (no RX during TX), so nothing echoes back.
std::optional<std::string> enable_kernel_rs485(int fd) {
  serial_rs485 rs485{};
  if (::ioctl(fd, TIOCGRS485, &rs485) != 0) return std::string(std::strerror(errno));
  rs485.flags |= SER_RS485_ENABLED | SER_RS485_RTS_ON_SEND;
  rs485.flags &= ~static_cast<__u32>(SER_RS485_RTS_AFTER_SEND | SER_RS485_RX_DURING_TX);
  if (::ioctl(fd, TIOCSRS485, &rs485) != 0) return std::string(std::strerror(errno));
  return std::nullopt;
}

// Behind a USB adapter the bytes come in bursts up to its latency timer apart: a framer
// must not take such a pause for the end of a frame, and replies are late by it.
void settle_adapter_latency(const config::RtuConfig& line, OpenedLine& opened) {
  auto timer = find_latency_timer(line.device);
  if (!timer) return;
  if (line.low_latency && timer->value > std::chrono::milliseconds(1)) {
    std::string error;
    if (set_latency_timer(*timer, std::chrono::milliseconds(1), error))
      opened.notes.push_back(fmt::format("{}: USB adapter latency timer set to 1 ms", line.device));
    else
      opened.warnings.push_back(fmt::format("{}: cannot set the USB adapter latency timer {} to 1 ms: {}", line.device,
                                            timer->file.string(), error));
  }
  const auto frame_gap = config::line_timing(line).frame_gap;
  if (timer->value > frame_gap)
    opened.warnings.push_back(fmt::format(
        "{}: the USB adapter holds received bytes up to {} ms ({}), longer than the {} µs between frames at {} baud: "
        "replies are late by up to that; set low_latency: true, or write 1 there",
        line.device, timer->value.count(), timer->file.string(), frame_gap.count(), line.baud));
  opened.adapter_latency = timer->value;
}

}  // namespace

OpenedLine open_serial_line(Port& port, const config::RtuConfig& line) {
  boost::system::error_code ec;
  port.open(line.device, ec);
  if (ec) throw std::runtime_error(fmt::format("{}: cannot open: {}", line.device, ec.message()));
  // Asio's open leaves the line raw (no echo, no translation, CLOCAL | CREAD).
  set_baud(port, line);
  port.set_option(Port::character_size(8), ec);
  set_or_throw(line.device, "8 data bits", ec);
  port.set_option(Port::parity(parity_of(line.parity)), ec);
  set_or_throw(line.device, "the parity", ec);
  port.set_option(Port::stop_bits(line.stop_bits == 2 ? Port::stop_bits::two : Port::stop_bits::one), ec);
  set_or_throw(line.device, "the stop bits", ec);
  port.set_option(Port::flow_control(Port::flow_control::none), ec);
  set_or_throw(line.device, "no flow control", ec);

  OpenedLine opened;
  auto& warnings = opened.warnings;
  const int fd = port.native_handle();
  switch (line.rs485) {
    case config::Rs485Direction::kernel:
      if (const auto error = enable_kernel_rs485(fd))
        warnings.push_back(fmt::format("{}: the driver refuses the kernel's RS-485 mode ({}); the transceiver's "
                                       "direction is not switched (rs485: rts, or an adapter that switches itself)",
                                       line.device, *error));
      break;
    case config::Rs485Direction::rts:
      if (!set_rts(fd, false))
        warnings.push_back(fmt::format("{}: the driver refuses to set RTS ({}); the transceiver's direction is not "
                                       "switched", line.device, std::strerror(errno)));
      break;
    case config::Rs485Direction::off: break;
  }
  settle_adapter_latency(line, opened);
  return opened;
}

bool set_rts(int fd, bool asserted) {
  int bits = TIOCM_RTS;
  return ::ioctl(fd, asserted ? TIOCMBIS : TIOCMBIC, &bits) == 0;
}

std::optional<int> output_queue(int fd) {
  int queued = 0;
  if (::ioctl(fd, TIOCOUTQ, &queued) != 0) return std::nullopt;
  return queued;
}

std::optional<bool> transmitter_empty(int fd) {
  int status = 0;
  if (::ioctl(fd, TIOCSERGETLSR, &status) != 0) return std::nullopt;
  return (status & TIOCSER_TEMT) != 0;
}

}  // namespace unima::io
