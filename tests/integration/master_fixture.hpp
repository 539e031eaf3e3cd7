#pragma once
// Master mode against simulated foreign slaves: tests/sim's foreign-slave-sim on a
// pseudo-terminal and/or TCP, with its frame log (the bytes as on the wire) and its
// control socket, and the daemon in master mode driving it.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tests/integration/bridge_fixture.hpp"

namespace unima::test {

/// One frame the simulator heard (rx) or sent (tx).
struct SimFrame {
  std::int64_t micros = 0;  // steady clock
  bool rx = true;
  bool rtu = true;
  std::string hex;          // "01 03 04 24 00 02 85 30"
};

class SlaveSim {
 public:
  /// Starts the simulator with `slaves` ("1=sic184-v3", "2=stepper-driver,dead"), on a pty
  /// at DIR/ttySIM when `pty`, on a free TCP port when `tcp`; `wire_baud` not 0: the
  /// simulator plays that line's wire times (its --baud).
  SlaveSim(const TempDir& dir, const std::vector<std::string>& slaves, bool pty = true, bool tcp = false,
           unsigned wire_baud = 0);
  ~SlaveSim();
  SlaveSim(const SlaveSim&) = delete;
  SlaveSim& operator=(const SlaveSim&) = delete;

  bool ready() const { return ready_; }
  const std::string& pty() const { return pty_; }
  std::uint16_t tcp_port() const { return tcp_port_; }
  std::vector<SimFrame> frames() const;
  /// Waits until a frame with exactly these bytes was heard (rx) or sent (tx).
  bool wait_for_frame(const std::string& hex, bool rx = true, std::chrono::milliseconds timeout = 5000ms) const;
  /// One control line and its answer ("count 1" -> "count 17").
  std::string control(const std::string& line) const;
  std::string output() const;

 private:
  std::filesystem::path out_path_, frames_path_, control_path_;
  std::string pty_;
  std::uint16_t tcp_port_ = 0;
  std::unique_ptr<test_support::ChildProcess> process_;
  bool ready_ = false;
};


class MasterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    config.mode = "master";
    config.banks.clear();  // the default layout: C at 0x1020, W at 0x3000, X at 0x3010
    config.devices.clear();
    config.log_level = "debug";
    config.modbus_port = free_port();
    config.feed_port = free_port();
    config.status_socket = (dir.path() / "control.sock").string();
  }
  /// Starts the simulator (on a pty) with `slaves`, and points the config's line at it
  /// (38400 baud); `wire`: the simulator answers when a line at that speed would have.
  void simulate(const std::vector<std::string>& slaves, bool tcp = false, bool wire = false);
  static constexpr unsigned line_baud = 38400;
  /// Starts the daemon and waits until its TCP slave accepts connections.
  void start();
  /// C+(output-1), read over the daemon's TCP slave (bank C at its default 0x1020).
  std::optional<std::uint16_t> output(unsigned n);
  bool output_becomes(unsigned n, std::uint16_t value, std::chrono::milliseconds timeout = 5000ms);
  std::string diagnostics() const;

  static constexpr int c_bank = 0x1020;
  static constexpr int online_bits = c_bank + 0x13;
  static constexpr int w_bank = 0x3000;
  static constexpr int x_bank = 0x3010;

  TempDir dir;
  BridgeConfig config;
  std::unique_ptr<SlaveSim> sim;
  std::unique_ptr<Daemon> daemon;
};

}  // namespace unima::test
