// The monitor's command filter (seed 004 §8, SPEC §5): address, function, register range
// with "xx" for any, and what a register range means for each kind of query.

#include <gtest/gtest.h>

#include <vector>

#include "monitor/command_filter.hpp"

namespace unima::monitor {
namespace {

using Bytes = std::vector<std::uint8_t>;

const Bytes read_0x0200_x16 = {0x04, 0x02, 0x00, 0x00, 0x10};  // 0x0200..0x020F
const Bytes write_0x0205 = {0x06, 0x02, 0x05, 0x12, 0x34};

TEST(CommandFilter, ParsesEveryKeyInDecimalOrHex) {
  const auto f = parse_command_filter("ad=3 fn=6 from=0x0200 to=0x0210");
  EXPECT_EQ(f.address, 3);
  EXPECT_EQ(f.function, 6);
  EXPECT_EQ(f.from, 0x0200);
  EXPECT_EQ(f.to, 0x0210);
  EXPECT_EQ(f.describe(), "ad=3 fn=6 from=0x0200 to=0x0210");
  EXPECT_EQ(parse_command_filter("fn=0x10").function, 16);
}

TEST(CommandFilter, AnyKeyMayBeLeftOutOrBeXx) {
  EXPECT_TRUE(parse_command_filter("").passes_everything());
  EXPECT_TRUE(parse_command_filter("ad=xx fn=xx from=xx to=xx").passes_everything());
  EXPECT_TRUE(parse_command_filter("ad=xx fn=xx from=0x0000 to=0xFFFF").passes_everything());
  const auto f = parse_command_filter("fn=4");
  EXPECT_FALSE(f.address);
  EXPECT_EQ(f.from, 0x0000);
  EXPECT_EQ(f.to, 0xFFFF);
  EXPECT_EQ(parse_command_filter("ad=xx").describe(), "ad=xx fn=xx from=0x0000 to=0xFFFF");
}

TEST(CommandFilter, BadExpressionsNameTheirFault) {
  const auto message = [](const std::string& expression) {
    try {
      parse_command_filter(expression);
    } catch (const FilterSyntaxError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message("reg=5"), "filter: unknown key 'reg' (keys: ad, fn, from, to)");
  EXPECT_EQ(message("ad=256"), "filter: ad='256' is not xx or a number 0..255");
  EXPECT_EQ(message("from=0x10000"), "filter: from='0x10000' is not xx or a number 0..65535");
  EXPECT_EQ(message("ad"), "filter: 'ad' is not key=value (keys: ad, fn, from, to)");
  EXPECT_EQ(message("ad=1 ad=2"), "filter: 'ad' is given twice");
  EXPECT_EQ(message("from=0x0300 to=0x0200"), "filter: from=0x0300 is after to=0x0200");
}

TEST(CommandFilter, AddressAndFunction) {
  const auto f = parse_command_filter("ad=3 fn=6");
  EXPECT_TRUE(f.matches(3, write_0x0205));
  EXPECT_FALSE(f.matches(4, write_0x0205));
  EXPECT_FALSE(f.matches(3, read_0x0200_x16));
  EXPECT_FALSE(f.matches(std::nullopt, write_0x0205));  // a frame too short for an address
  EXPECT_FALSE(f.matches(3, {}));
  EXPECT_TRUE(CommandFilter{}.matches(std::nullopt, {}));
}

// A read of N registers from `start` touches [start, start + N - 1]; it passes when that
// overlaps [from, to] at all.
TEST(CommandFilter, AReadOfNRegistersPassesWhenItsSpanOverlapsTheRange) {
  const auto pass = [](const char* expression, const Bytes& pdu) { return parse_command_filter(expression).matches(1, pdu); };
  EXPECT_TRUE(pass("from=0x0200 to=0x0200", read_0x0200_x16));  // first register
  EXPECT_TRUE(pass("from=0x020F to=0x0300", read_0x0200_x16));  // last register
  EXPECT_TRUE(pass("from=0x0205 to=0x0206", read_0x0200_x16));  // inside
  EXPECT_TRUE(pass("from=0x0100 to=0x0300", read_0x0200_x16));  // around
  EXPECT_FALSE(pass("from=0x0210 to=0x0300", read_0x0200_x16));  // just after
  EXPECT_FALSE(pass("from=0x0100 to=0x01FF", read_0x0200_x16));  // just before
  EXPECT_EQ(touched_ranges(read_0x0200_x16).count, 1);
  EXPECT_EQ(touched_ranges(read_0x0200_x16).ranges[0].last, 0x020F);
}

TEST(CommandFilter, SingleWritesTouchOneRegisterMultipleWritesTheirSpan) {
  EXPECT_TRUE(parse_command_filter("from=0x0205 to=0x0205").matches(1, write_0x0205));
  EXPECT_FALSE(parse_command_filter("from=0x0206 to=0x0210").matches(1, write_0x0205));
  const Bytes write_many = {0x10, 0x02, 0x00, 0x00, 0x02, 0x04, 0xAB, 0xCD, 0x12, 0x34};  // 0x0200..0x0201
  EXPECT_TRUE(parse_command_filter("from=0x0201 to=0x0201").matches(1, write_many));
  EXPECT_FALSE(parse_command_filter("from=0x0202 to=0x0202").matches(1, write_many));
  const Bytes write_coil = {0x05, 0x00, 0x13, 0xFF, 0x00};
  EXPECT_TRUE(parse_command_filter("from=0x0013 to=0x0013").matches(1, write_coil));
}

TEST(CommandFilter, ReadWriteMultipleTouchesBothRanges) {
  // Function 23: read 0x0010..0x0011, write 0x0300.
  const Bytes pdu = {0x17, 0x00, 0x10, 0x00, 0x02, 0x03, 0x00, 0x00, 0x01, 0x02, 0x00, 0x07};
  EXPECT_TRUE(parse_command_filter("from=0x0011 to=0x0011").matches(1, pdu));
  EXPECT_TRUE(parse_command_filter("from=0x0300 to=0x0300").matches(1, pdu));
  EXPECT_FALSE(parse_command_filter("from=0x0100 to=0x0200").matches(1, pdu));
}

TEST(CommandFilter, ASpanRunningPastTheEndIsClipped) {
  const Bytes read_at_top = {0x03, 0xFF, 0xF0, 0x00, 0x7B};  // 123 registers from 0xFFF0
  const auto touched = touched_ranges(read_at_top);
  ASSERT_EQ(touched.count, 1);
  EXPECT_EQ(touched.ranges[0].last, 0xFFFF);
  EXPECT_TRUE(parse_command_filter("from=0xFFFF to=0xFFFF").matches(1, read_at_top));
  EXPECT_FALSE(parse_command_filter("from=0x0000 to=0x0010").matches(1, read_at_top));
}

// A query without a data address passes only while the register range is not filtered.
TEST(CommandFilter, FunctionsWithoutARegisterPassOnlyAnUnfilteredRange) {
  const Bytes device_id = {0x2B, 0x0E, 0x01, 0x00};
  const Bytes diagnostics = {0x08, 0x00, 0x00, 0x12, 0x34};
  const Bytes truncated_read = {0x04, 0x02, 0x00};
  for (const auto& pdu : {device_id, diagnostics, truncated_read}) {
    EXPECT_EQ(touched_ranges(pdu).count, 0);
    EXPECT_TRUE(parse_command_filter("ad=1").matches(1, pdu));
    EXPECT_TRUE(parse_command_filter("from=0x0000 to=0xFFFF").matches(1, pdu));
    EXPECT_FALSE(parse_command_filter("from=0x0000 to=0xFFFE").matches(1, pdu));
    EXPECT_FALSE(parse_command_filter("from=0x0200").matches(1, pdu));
  }
  EXPECT_TRUE(parse_command_filter("fn=43").matches(1, device_id));
}

TEST(CommandFilter, ReadCountZeroTouchesItsStart) {
  const Bytes read_none = {0x04, 0x02, 0x00, 0x00, 0x00};
  EXPECT_TRUE(parse_command_filter("from=0x0200 to=0x0200").matches(1, read_none));
  EXPECT_FALSE(parse_command_filter("from=0x0201 to=0x0300").matches(1, read_none));
}

}  // namespace
}  // namespace unima::monitor
