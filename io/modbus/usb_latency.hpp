#pragma once
// The latency timer of a USB serial adapter (FTDI and others): the adapter holds received
// bytes up to this long before it sends them to the host, 16 ms by default. Longer than a
// line's t3.5 it hides the silences between frames and delays every reply. The kernel
// shows it at /sys/bus/usb-serial/devices/<tty>/latency_timer.

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>

namespace unima::io {

struct LatencyTimer {
  std::filesystem::path file;
  std::chrono::milliseconds value{0};
};

/// The latency timer of the adapter behind `device`, matched through the device's real
/// path (so /dev/serial/by-id/... links work); nullopt for a device that has none (a
/// built-in UART, a pseudo-terminal). `sysfs` is "/sys" but for tests.
std::optional<LatencyTimer> find_latency_timer(const std::string& device,
                                               const std::filesystem::path& sysfs = "/sys");

/// Writes a new value; false with `error` set when the kernel refuses (e.g. not root).
bool set_latency_timer(LatencyTimer& timer, std::chrono::milliseconds value, std::string& error);

}  // namespace unima::io
