#pragma once
// The commands a fleet may send (SPEC §12, `commands: true`): `<prefix>/set/W/<offset>`
// with the register's value, `<prefix>/set/X/<bit>` with 0 or 1. Each is checked here,
// then applied by the bridge exactly like a Modbus write (io::MqttService::take_command),
// and answered on `<prefix>/set/result`. Pure.

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

#include "banks/bank_id.hpp"

namespace unima::mqtt {

struct Command {
  banks::BankId bank = banks::BankId::W;
  std::uint16_t offset = 0;  // W: the register; X: the bit
  std::uint16_t value = 0;   // W: the register's value; X: 0 or 1
};

/// `subtopic` is what follows "<prefix>/set/" ("W/3", "X/0x0A"); the payload a number.
/// Else the reason, for the result message.
std::variant<Command, std::string> parse_command(std::string_view subtopic, std::string_view payload);

/// {"topic":…,"ok":true,"error":null} or with ok false and the reason.
std::string command_result(std::string_view topic, const std::string& error);

}  // namespace unima::mqtt
