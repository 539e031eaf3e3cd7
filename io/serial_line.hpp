#pragma once
// The serial line under the RTU port: opening it with the seed's settings (seed §4.1: 8
// data bits, parity, stop bits, baud), the transceiver's direction (the kernel's RS-485
// mode, or RTS raised by the port while it sends), and what the UART tells about its
// transmitter. Linux ioctls, kept apart from the port's protocol logic.

#include <optional>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "platform/asio.hpp"

namespace unima::io {

/// Opens `line.device` into `port` and sets it up. Throws std::runtime_error naming the
/// device and what failed. Returns warnings: things that work, but maybe not as meant.
std::vector<std::string> open_serial_line(asio::serial_port& port, const config::RtuConfig& line);

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
