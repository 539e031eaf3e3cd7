#pragma once
// The feed protocol's JSON lines (SPEC §6). In:
//   {"addr":5,"slot":0,"offset":33,"values":[853,854]}
//   {"addr":5,"slot":0,"device":"usc","offset":3,"values":[1500]}  (one of a unit's components)
// Out: {"bank":"W","offset":3,"value":1234} per published register, {"error":"…"} per
// rejected line. Pure; the socket lives in the daemon.

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

#include "banks/bank_id.hpp"
#include "unimabus/telegram.hpp"

namespace unima::unimabus {

/// A telegram, or why the line is not one.
using FeedLine = std::variant<Telegram, std::string>;

/// Parses one line (without its newline). Values may be written -32768..65535; negative
/// ones are stored as two's complement. A "t" field (replay files) is accepted and ignored.
/// Whatever the line holds, the answer is a telegram or a message: nothing is thrown.
FeedLine parse_feed_line(std::string_view line);

/// A line of a recording (SPEC §6 `record`, `replay`): a feed telegram plus "t", the
/// seconds since the recording began.
struct RecordedTelegram {
  double t = 0;
  Telegram telegram;
};
using RecordedLine = std::variant<RecordedTelegram, std::string>;
RecordedLine parse_recorded_line(std::string_view line);
/// `{"t":1.250000,"addr":5,"slot":0,"device":"usc","offset":3,"values":[1500]}\n`;
/// parse_recorded_line reads it back as the same telegram.
std::string format_recorded(const Telegram& telegram, double t);

/// `{"bank":"W","offset":3,"value":1234}\n`
std::string format_change(banks::BankId bank, std::uint16_t offset, std::uint16_t value);
/// `{"error":"…"}\n`, the message JSON-escaped.
std::string format_error(std::string_view message);

}  // namespace unima::unimabus
