#include "unimabus/feed_codec.hpp"

#include <nlohmann/json.hpp>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "banks/table_catalog.hpp"
#include "platform/json_text.hpp"

namespace unima::unimabus {

namespace {

// Non-negative integers parse as unsigned: compare them so, as get<long>() wraps those
// above LONG_MAX into negatives (2^64-1 would pass as -1).
bool above(const nlohmann::json& value, long max) {
  return value.is_number_unsigned() && value.get<std::uint64_t>() > static_cast<std::uint64_t>(max);
}

// Reads an integer field within [min, max]; returns an error message or "".
std::string integer(const nlohmann::json& object, const char* key, long min, long max, long& out) {
  const auto it = object.find(key);
  if (it == object.end()) return fmt::format("missing \"{}\"", key);
  if (!it->is_number_integer()) return fmt::format("\"{}\" must be an integer", key);
  if (above(*it, max)) return fmt::format("\"{}\" must be {}..{}, not {}", key, min, max, it->get<std::uint64_t>());
  out = it->get<long>();
  if (out < min || out > max) return fmt::format("\"{}\" must be {}..{}, not {}", key, min, max, out);
  return {};
}

}  // namespace

namespace {

// The fields of a telegram in a parsed line; "t" is allowed when `timed`.
std::variant<Telegram, std::string> telegram_of(const nlohmann::json& object, bool timed) {
  if (!object.is_object()) return std::string("expected an object like {\"addr\":5,\"slot\":0,\"offset\":33,\"values\":[853]}");
  for (const auto& [key, value] : object.items()) {
    (void)value;
    if (key != "addr" && key != "slot" && key != "device" && key != "offset" && key != "values" && key != "t")
      return fmt::format("unknown field \"{}\" (fields: addr, slot, device, offset, values{})", key, timed ? ", t" : "");
  }
  long address = 0, slot = 0, offset = 0;
  for (auto error : {integer(object, "addr", 0, 255, address), integer(object, "slot", 0, 7, slot),
                     integer(object, "offset", 0, 0xFFFF, offset)})
    if (!error.empty()) return error;
  const auto values = object.find("values");
  if (values == object.end()) return std::string("missing \"values\"");
  if (!values->is_array() || values->empty()) return std::string("\"values\" must be a non-empty array of integers");
  if (offset + values->size() > 0x10000) return std::string("\"offset\" + the number of values runs past 0xFFFF");
  Telegram telegram;
  if (const auto device = object.find("device"); device != object.end()) {
    if (!device->is_string()) return std::string("\"device\" must be a device type like \"usc\"");
    telegram.device = banks::find_device_type(device->get_ref<const std::string&>());
    if (!telegram.device)
      return fmt::format("unknown device type \"{}\" (known: {})", device->get_ref<const std::string&>(),
                         fmt::join(banks::device_type_ids(), ", "));
    if (slot != 0) return std::string("\"device\" names a D_N device (slot 0); IO modules are named by their slot");
  }
  telegram.address = static_cast<std::uint8_t>(address);
  telegram.slot = static_cast<std::uint8_t>(slot);
  telegram.offset = static_cast<std::uint16_t>(offset);
  telegram.values.reserve(values->size());
  for (const auto& v : *values) {
    if (!v.is_number_integer()) return std::string("\"values\" must hold integers only");
    if (above(v, 65535)) return fmt::format("value {} is outside -32768..65535", v.get<std::uint64_t>());
    const auto n = v.get<long>();
    if (n < -32768 || n > 65535) return fmt::format("value {} is outside -32768..65535", n);
    telegram.values.push_back(static_cast<std::uint16_t>(n));
  }
  return telegram;
}

}  // namespace

FeedLine parse_feed_line(std::string_view line) {
  auto parsed = platform::parse_json_text(line);
  if (auto* error = std::get_if<std::string>(&parsed)) return std::move(*error);
  return telegram_of(std::get<nlohmann::json>(parsed), true);
}

RecordedLine parse_recorded_line(std::string_view line) {
  auto parsed = platform::parse_json_text(line);
  if (auto* error = std::get_if<std::string>(&parsed)) return std::move(*error);
  const auto& object = std::get<nlohmann::json>(parsed);
  auto telegram = telegram_of(object, true);
  if (auto* error = std::get_if<std::string>(&telegram)) return std::move(*error);
  const auto t = object.find("t");
  if (t == object.end()) return std::string("missing \"t\", the seconds since the recording began");
  if (!t->is_number() || !(t->get<double>() >= 0) || t->get<double>() > 1e9)
    return std::string("\"t\" must be a number of seconds from 0");
  return RecordedTelegram{t->get<double>(), std::get<Telegram>(std::move(telegram))};
}

std::string format_recorded(const Telegram& telegram, double t) {
  std::string line = fmt::format("{{\"t\":{:.6f},\"addr\":{},\"slot\":{},", t, telegram.address, telegram.slot);
  if (telegram.device) line += fmt::format("\"device\":\"{}\",", telegram.device->id);
  line += fmt::format("\"offset\":{},\"values\":[{}]}}\n", telegram.offset, fmt::join(telegram.values, ","));
  return line;
}

std::string format_change(banks::BankId bank, std::uint16_t offset, std::uint16_t value) {
  return fmt::format("{{\"bank\":\"{}\",\"offset\":{},\"value\":{}}}\n", banks::bank_name(bank), offset, value);
}

std::string format_error(std::string_view message) {
  return nlohmann::json{{"error", message}}.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace unima::unimabus
