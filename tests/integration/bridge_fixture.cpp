#include "tests/integration/bridge_fixture.hpp"

#include <cerrno>

namespace unima::test {

ModbusClient::ModbusClient(std::uint16_t port, int unit) : ModbusClient(modbus_new_tcp("127.0.0.1", port), unit) {}

ModbusClient::ModbusClient(modbus_t* ctx, int unit) : master_(ctx, unit, 3) {}

ModbusClient::~ModbusClient() = default;

std::optional<std::vector<std::uint16_t>> ModbusClient::read_input(int address, int count) {
  std::vector<std::uint16_t> values(static_cast<std::size_t>(count));
  if (modbus_read_input_registers(*master_, address, count, values.data()) != count) {
    last_error_ = errno;
    return std::nullopt;
  }
  return values;
}

std::optional<std::vector<std::uint16_t>> ModbusClient::read_holding(int address, int count) {
  std::vector<std::uint16_t> values(static_cast<std::size_t>(count));
  if (modbus_read_registers(*master_, address, count, values.data()) != count) {
    last_error_ = errno;
    return std::nullopt;
  }
  return values;
}

bool ModbusClient::write(int address, std::uint16_t value) {
  if (modbus_write_register(*master_, address, value) == 1) return true;
  last_error_ = errno;
  return false;
}

bool ModbusClient::write_many(int address, const std::vector<std::uint16_t>& values) {
  const int n = static_cast<int>(values.size());
  if (modbus_write_registers(*master_, address, n, values.data()) == n) return true;
  last_error_ = errno;
  return false;
}

void BridgeTest::start() {
  daemon = std::make_unique<Daemon>(dir, config.yaml());
  if (config.modbus_port != 0) {
    ASSERT_TRUE(wait_for_port(config.modbus_port)) << daemon->log();
  }
  if (config.transport == "feed" && config.feed_listen.empty()) {
    ASSERT_TRUE(wait_for_port(config.feed_port)) << daemon->log();
  }
}

Socket BridgeTest::feed_client() {
  auto feed = config.feed_listen.starts_with("unix:") ? Socket::unix_socket(config.feed_listen.substr(5))
                                                      : Socket::tcp(config.feed_port);
  EXPECT_TRUE(feed.valid());
  EXPECT_TRUE(feed.wait_for_line(R"({"bank":"C","offset":18,"value":0})")) << "no snapshot";
  return feed;
}

void BridgeTest::feed_and_wait(Socket& feed, const std::string& telegram, int check_address, std::uint16_t expected) {
  feed.send(telegram + "\n");
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.connected());
  ASSERT_TRUE(eventually([&] {
    auto values = client.read_input(check_address, 1);
    return values && (*values)[0] == expected;
  })) << "register 0x" << std::hex << check_address << " never read " << expected << "\n"
      << daemon->log();
}

}  // namespace unima::test
