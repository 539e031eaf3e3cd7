// The simulated foreign slaves checked by an independent Modbus master, libmodbus: so that
// the master's tests against them do not rest on one implementation talking to itself.

#include <gtest/gtest.h>
#include <modbus/modbus.h>

#include <bit>
#include <cerrno>

#include "tests/integration/master_fixture.hpp"
#include "tests/support/peers/libmodbus_master.hpp"

namespace unima::test {
namespace {

using test_support::LibmodbusMaster;

TEST(SlaveSim, StepperDriverOverRtuAsLibmodbusSeesIt) {
  TempDir dir;
  SlaveSim sim(dir, {"1=stepper-driver"});
  ASSERT_TRUE(sim.ready()) << sim.output();
  LibmodbusMaster m(modbus_new_rtu(sim.pty().c_str(), 9600, 'N', 8, 1), 1);
  ASSERT_TRUE(m.connected());
  std::uint16_t values[2] = {};
  ASSERT_EQ(modbus_read_registers(*m, 0, 2, values), 2) << modbus_strerror(errno);
  EXPECT_EQ(values[0], 180);
  EXPECT_EQ(values[1], 8);
  // Seed 002 §6 (1), byte for byte, request and response.
  const std::uint8_t request[] = {0x01, 0x03, 0x00, 0x00, 0x00, 0x02};
  ASSERT_EQ(modbus_send_raw_request(*m, request, sizeof request), 8);
  std::uint8_t response[MODBUS_RTU_MAX_ADU_LENGTH];
  const int n = modbus_receive_confirmation(*m, response);
  ASSERT_EQ(n, 9);
  EXPECT_EQ(Bytes(response, response + n), (Bytes{0x01, 0x03, 0x04, 0x00, 0xB4, 0x00, 0x08, 0xBB, 0xD3}));
  ASSERT_EQ(modbus_write_register(*m, 1, 4), 1);
  EXPECT_EQ(sim.control("get 1 1"), "value 4");
  ASSERT_EQ(modbus_write_bit(*m, 7, 1), 1);
  EXPECT_EQ(sim.control("coil 1 7"), "coil 1");
  // What the driver lacks: function 4 (exception 01), registers 58..72 (exception 02).
  EXPECT_EQ(modbus_read_input_registers(*m, 0, 1, values), -1);
  EXPECT_EQ(errno, EMBXILFUN);
  EXPECT_EQ(modbus_read_registers(*m, 57, 2, values), -1);
  EXPECT_EQ(errno, EMBXILADD);
}

TEST(SlaveSim, Sic184OverTcpAsLibmodbusSeesIt) {
  TempDir dir;
  SlaveSim sim(dir, {"1=sic184-v3", "2=sic184-v2"}, false, true);
  ASSERT_TRUE(sim.ready()) << sim.output();
  LibmodbusMaster v3(modbus_new_tcp("127.0.0.1", sim.tcp_port()), 1);
  ASSERT_TRUE(v3.connected());
  std::uint16_t regs[2] = {};
  ASSERT_EQ(modbus_read_registers(*v3, 1060, 2, regs), 2);
  EXPECT_FLOAT_EQ(std::bit_cast<float>(static_cast<std::uint32_t>(regs[0] | regs[1] << 16)), 4.5f);  // POS_ACT_REAL
  ASSERT_EQ(modbus_read_registers(*v3, 1020, 2, regs), 2);
  EXPECT_EQ(regs[0] | regs[1] << 16, 57600);  // low word first (seed 000 §4.1)
  std::uint8_t bits[8] = {};
  ASSERT_EQ(modbus_read_input_bits(*v3, 5000, 8, bits), 8);
  EXPECT_EQ(bits[0], 1);
  EXPECT_EQ(bits[1], 0);
  EXPECT_EQ(bits[2], 1);
  EXPECT_EQ(modbus_read_registers(*v3, 1006, 1, regs), -1);
  EXPECT_EQ(errno, EMBXILADD);
  modbus_set_slave(*v3, 2);
  ASSERT_EQ(modbus_read_registers(*v3, 10, 2, regs), 2);
  EXPECT_EQ(regs[0] | regs[1] << 16, 45440);  // XACT, seed 001 §3.2
  modbus_set_slave(*v3, 9);
  EXPECT_EQ(modbus_read_registers(*v3, 10, 1, regs), -1);  // no such unit: gateway exception
  EXPECT_EQ(errno, EMBXGTAR);
}

}  // namespace
}  // namespace unima::test
