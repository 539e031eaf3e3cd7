#pragma once
// The test's side of a Modbus RTU line. A pseudo-terminal whose slave side the daemon
// opens through a symlink, so that the line can go away and come back at the same path as
// a USB adapter does; the test holds the master side and plays the rest of the bus: the
// bus master, foreign slaves, noise. And socat joining two pseudo-terminals, for a
// libmodbus RTU master on one end and the daemon on the other.

#include <sys/types.h>

#include <modbus/modbus.h>

#include <filesystem>
#include <optional>
#include <vector>

#include "tests/integration/bridge_fixture.hpp"
#include "tests/integration/harness.hpp"

namespace unima::test {

/// An RTU ADU: address, PDU, CRC low byte first.
Bytes rtu_adu(std::uint8_t address, const Bytes& pdu);

class PtyLine {
 public:
  explicit PtyLine(std::filesystem::path link);
  ~PtyLine();
  PtyLine(const PtyLine&) = delete;
  PtyLine& operator=(const PtyLine&) = delete;

  const std::filesystem::path& link() const { return link_; }
  void write(const Bytes& bytes) const;
  /// Exactly n bytes, or fewer at the deadline.
  Bytes read(std::size_t n, std::chrono::milliseconds timeout = 3000ms) const;
  /// Closes the terminal and removes the link: the daemon's reads fail, its opens too.
  void hang_up();
  /// A new terminal behind the same link.
  void replace();

 private:
  void open_terminal();
  void close_terminal();
  std::filesystem::path link_;
  int master_ = -1;
  int slave_ = -1;  // kept open, so that the master side never sees a hang-up of its own
};

/// socat joining two pseudo-terminals at `a` and `b`; killed when the object goes.
class SocatLink {
 public:
  SocatLink(const std::filesystem::path& a, const std::filesystem::path& b);
  bool ready() const { return ready_; }

 private:
  test_support::ChildProcess socat_;
  bool ready_ = false;
};

/// libmodbus as an RTU master on a serial device.
class RtuMaster : public ModbusClient {
 public:
  RtuMaster(const std::filesystem::path& device, int baud, int unit = 1)
      : ModbusClient(modbus_new_rtu(device.c_str(), baud, 'N', 8, 1), unit) {}
};

}  // namespace unima::test
