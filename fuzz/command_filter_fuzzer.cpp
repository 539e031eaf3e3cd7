// Fuzz target: the monitor's command filter (SPEC §5, seed 004 §8) as the command line
// gives it (`unima-bridge monitor --filter 'ad=3 fn=6 from=0x0200 to=0x0210'`), and the
// query it is matched against.
//
// Input: the expression up to the first newline; after it, one query PDU to match, its
// first byte taken as the query's address.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "fuzz/fuzz_check.hpp"
#include "monitor/command_filter.hpp"

namespace {

using namespace unima;

// Whether a range the query touches overlaps the filter's, decided again from
// touched_ranges: the filter must agree with the rule it documents.
bool touches(const monitor::CommandFilter& filter, std::span<const std::uint8_t> pdu) {
  const auto touched = monitor::touched_ranges(pdu);
  for (std::uint8_t i = 0; i < touched.count; ++i)
    if (touched.ranges[i].first <= filter.to && touched.ranges[i].last >= filter.from) return true;
  return false;
}

void check_matching(const monitor::CommandFilter& filter, std::optional<std::uint8_t> address,
                    std::span<const std::uint8_t> pdu) {
  const auto touched = monitor::touched_ranges(pdu);
  FUZZ_CHECK(touched.count <= 2);
  for (std::uint8_t i = 0; i < touched.count; ++i) FUZZ_CHECK(touched.ranges[i].first <= touched.ranges[i].last);

  const bool matches = filter.matches(address, pdu);
  if (filter.passes_everything()) FUZZ_CHECK(matches);
  const bool by_address = !filter.address || address == filter.address;
  const bool by_function = !filter.function || (!pdu.empty() && pdu[0] == *filter.function);
  const bool by_range = !filter.filters_registers() || touches(filter, pdu);
  FUZZ_CHECK(matches == (by_address && by_function && by_range));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto text = std::string_view(reinterpret_cast<const char*>(data), size);
  const auto newline = text.find('\n');
  const auto expression = text.substr(0, newline);
  const auto query = newline == std::string_view::npos ? std::span<const std::uint8_t>{}
                                                       : std::span(data + newline + 1, size - newline - 1);
  const auto address = query.empty() ? std::nullopt : std::optional<std::uint8_t>(query[0]);
  const auto pdu = query.empty() ? query : query.subspan(1);

  monitor::CommandFilter filter;
  try {
    filter = monitor::parse_command_filter(expression);
  } catch (const monitor::FilterSyntaxError& e) {
    FUZZ_CHECK(std::string_view(e.what()).starts_with("filter: "));
    return 0;  // any other exception escapes, and the fuzzer reports it
  }
  FUZZ_CHECK(filter.from <= filter.to);
  // What `describe` prints (the monitor's header line) reads back as the same filter.
  FUZZ_CHECK(monitor::parse_command_filter(filter.describe()) == filter);
  check_matching(filter, address, pdu);
  check_matching(filter, std::nullopt, pdu);
  return 0;
}
