// Fuzz target: what a feed driver sends (SPEC §6), down io/unimabus/feed_transport's path:
// unimabus::LineSplitter cuts the stream into lines, parse_feed_line makes telegrams (or
// the answer {"error":…}), unimabus::TelegramRouter puts them into the banks of
// config/examples/chp-site.yaml, where three D_N share one address.
//
// Input: byte 0 chooses the line limit (SPEC §6's 64 KiB, or a few bytes so that the
// overlong path is reached with small inputs); the rest is the stream, cut into reads
// at the bytes 0xFF (never part of UTF-8 text, so a read boundary falls between lines or
// inside one).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

#include <nlohmann/json.hpp>

#include "fuzz/bridge_banks.hpp"
#include "fuzz/fuzz_check.hpp"
#include "unimabus/feed_codec.hpp"
#include "unimabus/line_splitter.hpp"

namespace {

using namespace unima;

bool same_telegram(const unimabus::Telegram& a, const unimabus::Telegram& b) {
  return a.address == b.address && a.slot == b.slot && a.offset == b.offset && a.values == b.values &&
         a.device == b.device;
}

// The answer to a refused line is one line of JSON holding the message, whatever bytes
// the message quotes: the driver reads it back, and no line can be forged into its stream.
void check_error_answer(const std::string& message) {
  FUZZ_CHECK(!message.empty());
  const auto answer = unimabus::format_error(message);
  FUZZ_CHECK(answer.back() == '\n' && answer.find('\n') == answer.size() - 1);
  const auto json = nlohmann::json::parse(answer);  // throws, and so aborts, when it is not JSON
  FUZZ_CHECK(json.is_object() && json.size() == 1 && json["error"].is_string());
}

void take_line(std::string_view line, std::size_t max_line, fuzz::BridgeBanks& banks) {
  FUZZ_CHECK(line.size() <= max_line && line.find('\n') == std::string_view::npos);
  auto parsed = unimabus::parse_feed_line(line);
  if (const auto* error = std::get_if<std::string>(&parsed)) return check_error_answer(*error);
  const auto& telegram = std::get<unimabus::Telegram>(parsed);
  FUZZ_CHECK(line.find('\0') == std::string_view::npos);  // a NUL is never the end of a line's JSON
  FUZZ_CHECK(!telegram.values.empty() && telegram.slot <= 7);
  FUZZ_CHECK(telegram.offset + telegram.values.size() <= 0x10000);
  FUZZ_CHECK(telegram.device == nullptr || telegram.slot == 0);

  // What a recording writes of it reads back as the same telegram (SPEC §6 `record`).
  const auto recorded = unimabus::format_recorded(telegram, 0.25);
  const auto back = unimabus::parse_recorded_line(std::string_view(recorded).substr(0, recorded.size() - 1));
  FUZZ_CHECK(std::holds_alternative<unimabus::RecordedTelegram>(back));
  FUZZ_CHECK(same_telegram(std::get<unimabus::RecordedTelegram>(back).telegram, telegram));

  const auto outcome = banks.router.apply(telegram);
  // Taken by one bank, refused with a message, or ignored: exactly one of them.
  FUZZ_CHECK(int{!outcome.updated.empty()} + int{!outcome.error.empty()} + int{outcome.ignored} == 1);
  if (!outcome.error.empty()) check_error_answer(outcome.error);
  for (const auto bank : outcome.updated) {
    FUZZ_CHECK(outcome.updated.size() == 1 && telegram.offset + telegram.values.size() <= banks.store.filled_length(bank));
    banks.store.set_online(bank, true);  // as the bridge does when its device is heard (unimabus::Presence)
    for (std::size_t i = 0; i < telegram.values.size(); ++i) {
      const auto offset = static_cast<std::uint16_t>(telegram.offset + i);
      FUZZ_CHECK(banks.store.measured(bank, offset) && banks.store.read(bank, offset) == telegram.values[i]);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::size_t max_line = (data[0] & 1) ? 64 * 1024 : 8 + data[0] % 64;
  fuzz::BridgeBanks banks(fuzz::example("chp-site.yaml"));
  unimabus::LineSplitter splitter(max_line);
  std::size_t line_bytes = 0;
  std::size_t lines = 0;
  std::size_t overlong = 0;
  const auto on_line = [&](std::string_view line) {
    ++lines;
    line_bytes += line.size();
    take_line(line, max_line, banks);
  };
  const auto on_overlong = [&] { ++overlong; };

  auto stream = std::string_view(reinterpret_cast<const char*>(data) + 1, size - 1);
  while (!stream.empty()) {
    const auto cut = stream.find('\xFF');
    splitter.feed(stream.substr(0, cut), on_line, on_overlong);
    stream.remove_prefix(cut == std::string_view::npos ? stream.size() : cut + 1);
  }
  // Nothing is made up: the lines hold fewer bytes than came, a line ends at a newline,
  // and a line is reported overlong once (the last one even before its newline).
  FUZZ_CHECK(line_bytes <= size);
  const auto newlines = static_cast<std::size_t>(std::count(data + 1, data + size, std::uint8_t{'\n'}));
  FUZZ_CHECK(lines <= newlines && lines + overlong <= newlines + 1);
  return 0;
}
