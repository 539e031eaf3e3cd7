// SPEC §11 access control over plain Modbus TCP, with the real daemon and libmodbus: the
// allow list applied at the connection, and on reload to the clients already connected;
// read_only answering every write with exception 01, changing nothing, monitored.

#include <modbus/modbus.h>

#include <csignal>

#include "tests/integration/bridge_fixture.hpp"

namespace unima::test {
namespace {

class Access : public BridgeTest {};

TEST_F(Access, OnlyPeersInTheAllowListMayConnect) {
  config.tcp_extra = ", allow: [10.0.0.0/8, 'fd00::/8']";
  start();
  {
    ModbusClient refused(config.modbus_port);
    EXPECT_FALSE(refused.read_input(0x0011, 1));
  }
  EXPECT_TRUE(daemon->wait_for_log("modbus tcp: 127.0.0.1:")) << daemon->log();
  EXPECT_TRUE(daemon->wait_for_log("is not in modbus.tcp.allow; closing its connection")) << daemon->log();
  // Refused again and again: logged once (then counted), never a line per connection.
  for (int i = 0; i < 20; ++i) {
    ModbusClient refused(config.modbus_port);
    EXPECT_FALSE(refused.read_input(0x0011, 1));
  }
  EXPECT_EQ(daemon->log_count("is not in modbus.tcp.allow"), 1u) << daemon->log();

  config.tcp_extra = ", allow: [10.0.0.0/8, 127.0.0.0/8]";
  daemon->rewrite_config(config.yaml());
  daemon->signal(SIGHUP);
  ASSERT_TRUE(daemon->wait_for_log("reloaded")) << daemon->log();
  ModbusClient allowed(config.modbus_port);
  EXPECT_TRUE(allowed.read_input(0x0011, 1)) << daemon->log();

  // A narrower list cuts the clients it leaves out at once.
  config.tcp_extra = ", allow: [10.0.0.0/8]";
  daemon->rewrite_config(config.yaml());
  daemon->signal(SIGHUP);
  ASSERT_TRUE(eventually([&] { return daemon->log_count("reloaded") == 2; })) << daemon->log();
  EXPECT_FALSE(allowed.read_input(0x0011, 1));
}

TEST_F(Access, ReadOnlyAnswersEveryWriteWithIllegalFunctionAndChangesNothing) {
  const auto log = dir.path() / "monitor.log";
  config.monitor_section = "monitor:\n  file: " + log.string() + "\n";
  start();
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.write(0x0100, 42));

  config.tcp_extra = ", read_only: true";
  daemon->rewrite_config(config.yaml());
  daemon->signal(SIGHUP);
  ASSERT_TRUE(daemon->wait_for_log("reloaded")) << daemon->log();
  EXPECT_FALSE(client.write(0x0100, 7));
  EXPECT_EQ(client.last_error(), EMBXILFUN);
  EXPECT_FALSE(client.write_many(0x0100, {1, 2}));
  EXPECT_EQ(client.last_error(), EMBXILFUN);
  EXPECT_EQ(client.read_holding(0x0100, 2), (std::vector<std::uint16_t>{42, 0x7FFF}));  // reads as ever
  EXPECT_TRUE(eventually([&] { return read_file(log).find("State=Err01") != std::string::npos; }))
      << read_file(log);
  EXPECT_NE(read_file(log).find("PDU=06 01 00 00 07 Response="), std::string::npos) << read_file(log);
}

}  // namespace
}  // namespace unima::test
