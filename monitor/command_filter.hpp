#pragma once
// The monitor's command filter (seed 004 §8 "Command filter", SPEC §5): address,
// function, register from, register to; "xx" = any. Pure.
//
// What "register range" means: a query passes when the data addresses it touches overlap
// [from, to]. A read or write of N registers (or coils) from `start` touches
// [start, start + N - 1] (clipped at 0xFFFF; N = 0 touches just `start`); functions 5 and 6
// touch their one address; function 23 touches its read range and its write range. A
// function without a data address (7, 8, 11, 17, 43, ...) or a query too short to carry
// one passes only while the range is the whole space 0x0000..0xFFFF, i.e. not filtered
// by register. The filter judges the query; the response does not matter.

#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace unima::monitor {

struct RegisterRange {
  std::uint16_t first = 0;
  std::uint16_t last = 0;
};

/// The data-address ranges a request PDU touches: none, one, or two (function 23).
struct TouchedRanges {
  RegisterRange ranges[2];
  std::uint8_t count = 0;
};
TouchedRanges touched_ranges(std::span<const std::uint8_t> request_pdu);

struct CommandFilter {
  std::optional<std::uint8_t> address;   // nullopt: xx
  std::optional<std::uint8_t> function;  // nullopt: xx
  std::uint16_t from = 0x0000;
  std::uint16_t to = 0xFFFF;

  bool filters_registers() const { return from != 0x0000 || to != 0xFFFF; }
  bool passes_everything() const { return !address && !function && !filters_registers(); }
  /// `address` and `pdu` of the query (AduView); a query with no address or no PDU passes
  /// only a filter on neither.
  bool matches(std::optional<std::uint8_t> address, std::span<const std::uint8_t> request_pdu) const;
  /// "ad=3 fn=6 from=0x0200 to=0x0210", "ad=xx ..." for any.
  std::string describe() const;
  bool operator==(const CommandFilter&) const = default;
};

class FilterSyntaxError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// The filter's fields, as the command line ("ad", "fn", "from", "to") and the YAML
/// section monitor.filter ("address", "function", "from", "to") name them.
enum class FilterField : std::uint8_t { address, function, from, to };

/// Sets `field` from its text: "xx" (any) or a number, decimal or 0x hex, in the field's
/// range. Throws FilterSyntaxError ("'256' is not xx or a number 0..255"). The one parser
/// of filter values, for the command line and the config alike.
void set_filter_field(CommandFilter& filter, FilterField field, std::string_view text);
/// Throws FilterSyntaxError ("from=0x0300 is after to=0x0200") when the range is empty.
void check_filter_range(const CommandFilter& filter);

/// Reads "ad=3 fn=6 from=0x0200 to=0x0210" (SPEC §5): any key may be left out, values are
/// decimal or 0x hex, "xx" means any; throws FilterSyntaxError naming the bad part.
CommandFilter parse_command_filter(std::string_view expression);

}  // namespace unima::monitor
