#pragma once
// The serial line under the RTU slave port and the master's RTU link — the one way the
// daemon opens a line: the seed's settings (seed §4.1: 8 data bits, parity, stop bits,
// baud, 14400 included), the transceiver's direction (the kernel's RS-485 mode, or RTS
// raised by the port while it sends), a USB adapter's latency timer, and what the UART
// tells about its transmitter. Linux ioctls, kept apart from the ports' protocol logic.

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "platform/asio.hpp"

namespace unima::io {

struct OpenedLine {
  std::vector<std::string> warnings;  // things that work, but maybe not as meant
  std::vector<std::string> notes;     // what was changed on the way (the adapter's latency timer)
  /// How long the USB adapter behind the line holds received bytes; 0 for a UART or pty.
  std::chrono::milliseconds adapter_latency{0};
};

/// Opens `line.device` into `port` and sets it up; with `line.low_latency` sets a USB
/// adapter's latency timer to 1 ms. Throws std::runtime_error naming the device and what
/// failed.
OpenedLine open_serial_line(asio::serial_port& port, const config::RtuConfig& line);

using config::parity_letter;

/// Asserts (true) or releases RTS; false when the driver refuses.
bool set_rts(int fd, bool asserted);
/// Bytes the driver has not yet sent; nullopt when it cannot tell.
std::optional<int> output_queue(int fd);
/// True once the UART's shift register is empty too; nullopt when the driver cannot tell.
std::optional<bool> transmitter_empty(int fd);

/// Sets a rate that has no Bxxxx constant (14400) through termios2. Returns 0 or errno.
/// In a file of its own: <asm/termbits.h> cannot share a translation unit with <termios.h>.
int set_custom_baud(int fd, unsigned baud);

}  // namespace unima::io
