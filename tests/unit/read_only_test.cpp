// modbus.tcp.read_only is the bridge's freeze switch (SPEC §11, issue 29 row 8): the one
// write path refuses every write while it is on, whichever way the write came in (a
// Modbus port, an MQTT command), and the config warns when MQTT commands are on with it.

#include <gtest/gtest.h>

#include <array>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "banks/write_path.hpp"
#include "config/config.hpp"
#include "tests/support/bank_layouts.hpp"

namespace unima {
namespace {

using Status = modbus::WriteResult::Status;

struct Journal final : banks::WriteJournal {
  std::uint64_t keep(std::span<const banks::WrittenValue> write) override {
    last.assign(write.begin(), write.end());
    return ++kept;
  }
  std::optional<std::uint16_t> pending(banks::BankId, std::uint16_t) const override { return std::nullopt; }
  std::uint64_t kept = 0;
  std::vector<banks::WrittenValue> last;
};

TEST(ReadOnly, AFrozenWritePathRefusesEveryWriteAndChangesNothingUntilThawed) {
  banks::RegisterStore store{banks::shapes_with({nullptr, nullptr, nullptr, nullptr})};
  int published = 0;
  store.set_change_listener([&](banks::BankId, std::uint16_t, std::uint16_t) { ++published; });
  banks::RegisterSpace space{banks::AddressMap({banks::bank_window(banks::BankId::W, 0x3000, 16),
                                                banks::bank_window(banks::BankId::X, 0x3010, 1)}),
                             store, banks::AccessRules{}};
  Journal journal;
  banks::WritePath writes{space, &journal};
  writes.freeze(true);
  const std::array<std::uint16_t, 1> value = {66};
  EXPECT_EQ(writes.write_registers(0x3003, value, nullptr).status, Status::read_only);  // every register
  const auto everything = modbus::WriteRights::nothing();
  EXPECT_EQ(writes.write_registers(0x3003, value, &everything).status, Status::read_only);  // before any right
  EXPECT_EQ(writes.write_bit(0x3010, 2, true, nullptr).status, Status::read_only);           // MQTT's X bits
  EXPECT_EQ(store.read(banks::BankId::W, 3), 0x7FFF);
  EXPECT_EQ(store.read(banks::BankId::X, 0), 0);
  EXPECT_EQ(journal.kept, 0u);
  EXPECT_EQ(published, 0);

  writes.freeze(false);
  EXPECT_EQ(writes.write_registers(0x3003, value, nullptr).status, Status::written);
  EXPECT_EQ(journal.kept, 1u);
  writes.commit(journal.last);  // durable
  EXPECT_EQ(store.read(banks::BankId::W, 3), 66);
}

config::Config config_of(const std::string& yaml) {
  config::Host host;
  host.name = "box";
  return config::parse_text(yaml, "bridge.yaml", host);
}

TEST(ReadOnly, ThePlainPortsReadOnlyFreezesTheBridgeAndTheTlsPortsIsItsOwn) {
  EXPECT_FALSE(config::writes_frozen(config_of("modbus:\n  tcp: {}\n")));
  EXPECT_TRUE(config::writes_frozen(config_of("modbus:\n  tcp: { read_only: true }\n")));
  EXPECT_FALSE(config::writes_frozen(config_of("")));
  EXPECT_FALSE(config::writes_frozen(
      config_of("modbus:\n  tls: { certificate: s.pem, key: s.key, ca: ca.pem, read_only: true }\n")));
}

TEST(ReadOnly, MqttCommandsWithReadOnlyAreWarnedOf) {
  const std::string mqtt = "mqtt: { broker: 'mqtt://127.0.0.1:1883', commands: true }\n";
  const auto warned = [](const config::Config& c) {
    for (const auto& w : config::warnings(c))
      if (w.find("mqtt.commands is true, but modbus.tcp.read_only is on") != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(warned(config_of("modbus:\n  tcp: { read_only: true }\n" + mqtt)));
  EXPECT_FALSE(warned(config_of("modbus:\n  tcp: { read_only: false }\n" + mqtt)));
  EXPECT_FALSE(warned(config_of("modbus:\n  tcp: { read_only: true }\nmqtt: { broker: 'mqtt://127.0.0.1:1883' }\n")));
}

TEST(ReadOnly, SparkplugCommandsWithReadOnlyAreWarnedOf) {
  const std::string sparkplug = "sparkplug: { broker: 'mqtt://127.0.0.1:1883', group_id: g, commands: true }\n";
  const auto warned = [](const config::Config& c) {
    for (const auto& w : config::warnings(c))
      if (w.find("sparkplug.commands is true, but modbus.tcp.read_only is on: every DCMD is refused") != std::string::npos)
        return true;
    return false;
  };
  EXPECT_TRUE(warned(config_of("modbus:\n  tcp: { read_only: true }\n" + sparkplug)));
  EXPECT_FALSE(warned(config_of("modbus:\n  tcp: { read_only: false }\n" + sparkplug)));
}

}  // namespace
}  // namespace unima
