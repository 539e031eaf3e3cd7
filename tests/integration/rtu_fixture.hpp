#pragma once
// A running bridge with a Modbus RTU slave on a pseudo-terminal (and its TCP slave and
// feed transport, as in every integration test).

#include <memory>
#include <string>

#include "tests/integration/bridge_fixture.hpp"
#include "tests/integration/rtu_line.hpp"

namespace unima::test {

class RtuTest : public BridgeTest {
 protected:
  void SetUp() override;
  /// Starts the daemon with modbus.rtu on `device` (the fixture's line when empty) and
  /// `more` appended at top level; waits until its ports serve.
  void start_rtu(const std::string& more = "", const std::string& device = "");
  std::string rtu_yaml(const std::string& device) const;
  /// Sends `query` on the line and reads `size` bytes of reply.
  Bytes exchange(const Bytes& query, std::size_t size);
  /// The reply to a read of W+0 (0x0100, readable_write_banks) is the next thing on the line.
  void expect_next_reply_is_to_a_read_of_w(std::uint16_t value);
  /// C+0x13 bit 15 (Modbus communication error), read over TCP.
  bool error_bit_set();

  unsigned baud = 19200;
  std::unique_ptr<PtyLine> line;
};

}  // namespace unima::test
