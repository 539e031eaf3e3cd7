#include "mqtt/command.hpp"

#include <charconv>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace unima::mqtt {

namespace {

// Decimal, or hex after 0x; the whole text, nothing else.
std::optional<long> integer(std::string_view text, bool allow_sign) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\n' || text.back() == '\r'))
    text.remove_suffix(1);
  const bool negative = text.starts_with('-');
  if (negative) {
    if (!allow_sign) return std::nullopt;
    text.remove_prefix(1);
  }
  int base = 10;
  if (text.starts_with("0x") || text.starts_with("0X")) {
    base = 16;
    text.remove_prefix(2);
  }
  long value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value, base);
  if (text.empty() || text.front() == '-' || text.front() == '+' || error != std::errc() || end != text.data() + text.size())
    return std::nullopt;
  return negative ? -value : value;
}

}  // namespace

std::variant<Command, std::string> parse_command(std::string_view subtopic, std::string_view payload) {
  const auto slash = subtopic.find('/');
  const auto bank = subtopic.substr(0, slash);
  if (slash == std::string_view::npos || (bank != "W" && bank != "X"))
    return std::string("commands are set/W/<offset> and set/X/<bit>");
  const auto place = integer(subtopic.substr(slash + 1), false);
  Command command;
  if (bank == "W") {
    command.bank = banks::BankId::W;
    if (!place || *place > 15) return fmt::format("W has the offsets 0..15, not '{}'", subtopic.substr(slash + 1));
    const auto value = integer(payload, true);
    if (!value || *value < -32768 || *value > 65535)
      return fmt::format("the payload must be a whole number -32768..65535, not '{}'", payload.substr(0, 40));
    command.value = static_cast<std::uint16_t>(*value);
  } else {
    command.bank = banks::BankId::X;
    if (!place || *place > 15) return fmt::format("X has the bits 0..15, not '{}'", subtopic.substr(slash + 1));
    const auto value = integer(payload, false);
    if (!value || *value > 1) return fmt::format("the payload must be 0 or 1, not '{}'", payload.substr(0, 40));
    command.value = static_cast<std::uint16_t>(*value);
  }
  command.offset = static_cast<std::uint16_t>(*place);
  return command;
}

std::string command_result(std::string_view topic, const std::string& error) {
  nlohmann::ordered_json result;
  result["topic"] = topic;
  result["ok"] = error.empty();
  result["error"] = error.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(error);
  return result.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace unima::mqtt
