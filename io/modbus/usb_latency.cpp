#include "io/modbus/usb_latency.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>

namespace unima::io {

namespace fs = std::filesystem;

namespace {
std::optional<std::chrono::milliseconds> read_ms(const fs::path& file) {
  std::ifstream in(file);
  long value = -1;
  if (!(in >> value) || value < 0) return std::nullopt;
  return std::chrono::milliseconds(value);
}
}  // namespace

std::optional<LatencyTimer> find_latency_timer(const std::string& device, const fs::path& sysfs) {
  std::error_code ec;
  const auto real = fs::canonical(device, ec);
  if (ec) return std::nullopt;
  const auto devices = sysfs / "bus" / "usb-serial" / "devices";
  for (const auto& entry : fs::directory_iterator(devices, ec)) {
    if (entry.path().filename() != real.filename()) continue;
    LatencyTimer timer;
    timer.file = entry.path() / "latency_timer";
    const auto value = read_ms(timer.file);
    if (!value) return std::nullopt;
    timer.value = *value;
    return timer;
  }
  return std::nullopt;
}

bool set_latency_timer(LatencyTimer& timer, std::chrono::milliseconds value, std::string& error) {
  {
    std::ofstream out(timer.file);
    out << value.count() << "\n";
    out.flush();
    if (!out) {
      error = std::strerror(errno);
      return false;
    }
  }
  const auto now = read_ms(timer.file);
  if (!now || *now != value) {
    error = "the value did not stick";
    return false;
  }
  timer.value = *now;
  return true;
}

}  // namespace unima::io
