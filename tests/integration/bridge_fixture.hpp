#pragma once
// A running bridge on the feed transport with a Modbus TCP slave, for the integration tests.

#include <gtest/gtest.h>
#include <modbus/modbus.h>

#include <memory>
#include <optional>

#include "tests/integration/harness.hpp"
#include "tests/support/peers/libmodbus_master.hpp"

namespace unima::test {

/// libmodbus as the SCADA side (an independent Modbus implementation), its calls made
/// typed and their errors kept.
class ModbusClient {
 public:
  explicit ModbusClient(std::uint16_t port, int unit = 1);
  virtual ~ModbusClient();
  ModbusClient(const ModbusClient&) = delete;
  ModbusClient& operator=(const ModbusClient&) = delete;

  bool connected() const { return master_.connected(); }
  std::optional<std::vector<std::uint16_t>> read_input(int address, int count);
  std::optional<std::vector<std::uint16_t>> read_holding(int address, int count);
  bool write(int address, std::uint16_t value);
  bool write_many(int address, const std::vector<std::uint16_t>& values);
  /// errno of the last failed call (EMBXILADD etc. for exceptions).
  int last_error() const { return last_error_; }

 protected:
  /// Takes `ctx` (TCP or RTU, nullptr when it could not be made) and connects it.
  ModbusClient(modbus_t* ctx, int unit);

 private:
  test_support::LibmodbusMaster master_;
  int last_error_ = 0;
};

class BridgeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    config.modbus_port = free_port();
    config.feed_port = free_port();
    config.status_socket = (dir.path() / "control.sock").string();
  }
  /// Starts the daemon on `config` and waits until its ports accept connections.
  void start();
  /// A feed client whose snapshot has been read up to its last line (C+0x12).
  Socket feed_client();
  /// Sends a telegram and waits until `check_address` reads `expected` over Modbus.
  void feed_and_wait(Socket& feed, const std::string& telegram, int check_address, std::uint16_t expected);

  TempDir dir;
  BridgeConfig config;
  std::unique_ptr<Daemon> daemon;
};

}  // namespace unima::test
