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
FeedLine parse_feed_line(std::string_view line);

/// `{"bank":"W","offset":3,"value":1234}\n`
std::string format_change(banks::BankId bank, std::uint16_t offset, std::uint16_t value);
/// `{"error":"…"}\n`, the message JSON-escaped.
std::string format_error(std::string_view message);

}  // namespace unima::unimabus
