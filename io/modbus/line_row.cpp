#include "io/modbus/line_row.hpp"

#include <fmt/format.h>

namespace unima::io {

status::LineStatus line_row(const config::LineConfig& line, bool open, const status::LineCounters& counters,
                            std::size_t queue) {
  const auto& serial = line.serial;
  return {.name = line.name,
          .role = config::line_role_name(line.role),
          .device = serial.device,
          .settings = fmt::format("{} 8{}{}", serial.baud, config::parity_letter(serial.parity), serial.stop_bits),
          .open = open,
          .counters = counters,
          .queue = queue};
}

}  // namespace unima::io
