// Capture blocks (MBS_RegC, seed 004 §7.1): which user outputs a foreign write or read sets.

#include <gtest/gtest.h>

#include <vector>

#include "modbus/capture.hpp"
#include "modbus/rtu/rtu_adu.hpp"

namespace unima::modbus {
namespace {

using Bytes = std::vector<std::uint8_t>;
using Via = Captured::Via;

Bytes adu(std::uint8_t address, const Bytes& pdu) {
  Bytes out(pdu.size() + 3);
  out.resize(write_rtu_adu(address, pdu, out));
  return out;
}

// The seed's example block: register 0x0202 of device 3 into output 2; and 0x0204 into 5.
const std::vector<CaptureRule> rules = {{3, 0x0202, 2}, {3, 0x0204, 5}, {4, 0x0202, 7}};

TEST(CaptureWrites, Function6OfTheDeviceAndRegister) {
  EXPECT_EQ(captured_writes(rules, adu(3, {0x06, 0x02, 0x02, 0x12, 0x34})),
            (std::vector<Captured>{{2, 0x1234, Via::write}}));
  EXPECT_EQ(captured_writes(rules, adu(4, {0x06, 0x02, 0x02, 0x00, 0x01})),
            (std::vector<Captured>{{7, 0x0001, Via::write}}));
}

TEST(CaptureWrites, AnotherDeviceOrRegisterIsNotCaptured) {
  EXPECT_TRUE(captured_writes(rules, adu(5, {0x06, 0x02, 0x02, 0x12, 0x34})).empty());
  EXPECT_TRUE(captured_writes(rules, adu(3, {0x06, 0x02, 0x03, 0x12, 0x34})).empty());
}

TEST(CaptureWrites, ABroadcastReachesTheDeviceToo) {
  EXPECT_EQ(captured_writes(rules, adu(0, {0x06, 0x02, 0x02, 0x00, 0x09})),
            (std::vector<Captured>{{2, 9, Via::write}, {7, 9, Via::write}}));
}

TEST(CaptureWrites, Function16CoveringTheRegister) {
  EXPECT_EQ(captured_writes(rules, adu(3, {0x10, 0x02, 0x01, 0x00, 0x04, 0x08, 0, 1, 0, 2, 0, 3, 0, 4})),
            (std::vector<Captured>{{2, 2, Via::write}, {5, 4, Via::write}}));
  EXPECT_TRUE(captured_writes(rules, adu(3, {0x10, 0x02, 0x05, 0x00, 0x01, 0x02, 0, 1})).empty());
  // A byte count that does not match the count is a malformed request: nothing taken.
  EXPECT_TRUE(captured_writes(rules, adu(3, {0x10, 0x02, 0x02, 0x00, 0x01, 0x04, 0, 1, 0, 2})).empty());
}

TEST(CaptureWrites, ReadsAndMalformedWritesCaptureNothing) {
  EXPECT_TRUE(captured_writes(rules, adu(3, {0x04, 0x02, 0x02, 0x00, 0x01})).empty());
  EXPECT_TRUE(captured_writes(rules, adu(3, {0x06, 0x02, 0x02, 0x12})).empty());
  EXPECT_TRUE(captured_writes(rules, Bytes{0x03, 0x06}).empty());
}

TEST(CaptureReads, Function4ResponseCoveringTheRegister) {
  const auto query = adu(3, {0x04, 0x02, 0x00, 0x00, 0x03});  // 0x0200..0x0202
  const auto response = adu(3, {0x04, 0x06, 0x00, 0x0A, 0x00, 0x0B, 0x01, 0x2C});
  EXPECT_EQ(captured_reads(rules, query, response), (std::vector<Captured>{{2, 300, Via::read}}));
}

TEST(CaptureReads, Function3AndSeveralBlocksInOneRead) {
  const auto query = adu(3, {0x03, 0x02, 0x02, 0x00, 0x03});  // 0x0202..0x0204
  const auto response = adu(3, {0x03, 0x06, 0x00, 0x01, 0x00, 0x02, 0x00, 0x03});
  EXPECT_EQ(captured_reads(rules, query, response), (std::vector<Captured>{{2, 1, Via::read}, {5, 3, Via::read}}));
}

TEST(CaptureReads, NothingFromExceptionsMismatchesOrOtherRanges) {
  const auto query = adu(3, {0x04, 0x02, 0x00, 0x00, 0x03});
  EXPECT_TRUE(captured_reads(rules, query, adu(3, {0x84, 0x02})).empty());
  EXPECT_TRUE(captured_reads(rules, query, adu(4, {0x04, 0x06, 0, 1, 0, 2, 0, 3})).empty());  // another slave
  EXPECT_TRUE(captured_reads(rules, query, adu(3, {0x03, 0x06, 0, 1, 0, 2, 0, 3})).empty());  // another function
  EXPECT_TRUE(captured_reads(rules, query, adu(3, {0x04, 0x04, 0, 1, 0, 2})).empty());        // too few values
  EXPECT_TRUE(captured_reads(rules, adu(3, {0x04, 0x01, 0x00, 0x00, 0x02}), adu(3, {0x04, 0x04, 0, 1, 0, 2})).empty());
  EXPECT_TRUE(captured_reads(rules, adu(3, {0x01, 0x02, 0x02, 0x00, 0x08}), adu(3, {0x01, 0x01, 0xFF})).empty());
}

}  // namespace
}  // namespace unima::modbus
