// The Modbus core: CRC, MBAP framing and the request handler, against the frames of the
// seeds (their CRCs are correct) and every exception case of SPEC §3.

#include <gtest/gtest.h>

#include <map>
#include <vector>

#include "modbus/rtu/crc16.hpp"
#include "modbus/mbap.hpp"
#include "modbus/request_handler.hpp"
#include "tests/support/map_registers.hpp"
#include "tests/support/seed_frames.hpp"

namespace unima::modbus {
namespace {

using Bytes = std::vector<std::uint8_t>;

std::uint16_t crc_on_wire(const Bytes& frame) {  // low byte first on the wire
  return static_cast<std::uint16_t>(frame[frame.size() - 2] | frame[frame.size() - 1] << 8);
}

TEST(Crc16, SeedFramesCarryTheirCrc) {
  const std::vector<Bytes> frames = {
      test_support::seed::read_query,              // seed 004 §5.1 query
      test_support::seed::read_response,        // seed 004 §5.1 response
      test_support::seed::write_query,              // seed 004 §5.2
  };
  for (const auto& frame : frames) {
    const Bytes body(frame.begin(), frame.end() - 2);
    EXPECT_EQ(crc16(body), crc_on_wire(frame));
  }
}

TEST(Crc16, EmptyInputIsTheInitialValue) { EXPECT_EQ(crc16({}), 0xFFFF); }

class Handler : public ::testing::Test {
 protected:
  Bytes handle(const Bytes& request) {
    std::array<std::uint8_t, max_pdu_size> response{};
    const auto n = handle_request(request, response, registers, options).length;
    return Bytes(response.begin(), response.begin() + static_cast<std::ptrdiff_t>(n));
  }
  // A readable window 0x0011..0x0014 and a writable one 0x0100..0x0101.
  test_support::MapRegisters registers{{{0x11, 0x0050}, {0x12, 0x7FFF}, {0x13, 3}, {0x14, 4}}, {{0x100, 0}, {0x101, 0}}};
  HandlerOptions options;
};

TEST_F(Handler, SeedReadOfTwoRegisters) {
  EXPECT_EQ(handle({0x04, 0x00, 0x11, 0x00, 0x02}), (Bytes{0x04, 0x04, 0x00, 0x50, 0x7F, 0xFF}));
}

TEST_F(Handler, SeedWriteIsEchoed) {
  EXPECT_EQ(handle({0x06, 0x01, 0x01, 0x09, 0x29}), (Bytes{0x06, 0x01, 0x01, 0x09, 0x29}));
  EXPECT_EQ(registers.writable[0x101], 0x0929);
}

TEST_F(Handler, Function3IsAnsweredLike4AndCanBeSwitchedOff) {
  EXPECT_EQ(handle({0x03, 0x00, 0x11, 0x00, 0x01}), (Bytes{0x03, 0x02, 0x00, 0x50}));
  options.read_holding_registers = false;
  EXPECT_EQ(handle({0x03, 0x00, 0x11, 0x00, 0x01}), (Bytes{0x83, 0x01}));
}

TEST_F(Handler, UnknownFunctionIsIllegalFunction) {
  EXPECT_EQ(handle({0x01, 0x00, 0x00, 0x00, 0x01}), (Bytes{0x81, 0x01}));
  EXPECT_EQ(handle({0x05, 0x00, 0x00, 0xFF, 0x00}), (Bytes{0x85, 0x01}));
  EXPECT_EQ(handle({0x41}), (Bytes{0xC1, 0x01}));
}

TEST_F(Handler, CountZeroIsIllegalAddress) { EXPECT_EQ(handle({0x04, 0x00, 0x11, 0x00, 0x00}), (Bytes{0x84, 0x02})); }

TEST_F(Handler, CountAboveTheMaximumIsIllegalAddress) {
  options.max_read_registers = max_read_registers_tcp;
  EXPECT_EQ(handle({0x04, 0x00, 0x11, 0x00, 124}), (Bytes{0x84, 0x02}));
  options.max_read_registers = max_read_registers_rtu;
  EXPECT_EQ(handle({0x04, 0x00, 0x11, 0x00, 126}), (Bytes{0x84, 0x02}));
  EXPECT_EQ(registers.reads, 0);
}

TEST_F(Handler, AnyRegisterOutsideIsIllegalAddress) {
  EXPECT_EQ(handle({0x04, 0x00, 0x10, 0x00, 0x02}), (Bytes{0x84, 0x02}));  // first one outside
  EXPECT_EQ(handle({0x04, 0x00, 0x14, 0x00, 0x02}), (Bytes{0x84, 0x02}));  // last one outside
  EXPECT_EQ(handle({0x04, 0xFF, 0xFF, 0x00, 0x02}), (Bytes{0x84, 0x02}));  // past 0xFFFF
}

TEST_F(Handler, WriteOutsideWritableIsIllegalAddress) {
  EXPECT_EQ(handle({0x06, 0x00, 0x11, 0x00, 0x01}), (Bytes{0x86, 0x02}));
}

TEST_F(Handler, MalformedLengthIsIllegalValue) {
  EXPECT_EQ(handle({0x04, 0x00, 0x11, 0x00}), (Bytes{0x84, 0x03}));
  EXPECT_EQ(handle({0x04, 0x00, 0x11, 0x00, 0x02, 0x00}), (Bytes{0x84, 0x03}));
  EXPECT_EQ(handle({0x06, 0x01, 0x01, 0x09}), (Bytes{0x86, 0x03}));
  EXPECT_EQ(handle({0x03}), (Bytes{0x83, 0x03}));
}

TEST_F(Handler, WriteMultipleRegisters) {
  EXPECT_EQ(handle({0x10, 0x01, 0x00, 0x00, 0x02, 0x04, 0x12, 0x34, 0x56, 0x78}), (Bytes{0x10, 0x01, 0x00, 0x00, 0x02}));
  EXPECT_EQ(registers.writable[0x100], 0x1234);
  EXPECT_EQ(registers.writable[0x101], 0x5678);
}

TEST_F(Handler, WriteMultipleIsAllOrNothing) {
  EXPECT_EQ(handle({0x10, 0x01, 0x01, 0x00, 0x02, 0x04, 0x12, 0x34, 0x56, 0x78}), (Bytes{0x90, 0x02}));
  EXPECT_EQ(registers.writable[0x101], 0);
}

TEST_F(Handler, WriteMultipleBadByteCountIsIllegalValue) {
  EXPECT_EQ(handle({0x10, 0x01, 0x00, 0x00, 0x02, 0x03, 0x12, 0x34, 0x56}), (Bytes{0x90, 0x03}));
  EXPECT_EQ(handle({0x10, 0x01, 0x00, 0x00, 0x02, 0x04, 0x12, 0x34, 0x56}), (Bytes{0x90, 0x03}));
  EXPECT_EQ(handle({0x10, 0x01, 0x00, 0x00}), (Bytes{0x90, 0x03}));
}

TEST_F(Handler, WriteMultipleCountOutOfRangeIsIllegalAddress) {
  EXPECT_EQ(handle({0x10, 0x01, 0x00, 0x00, 0x00, 0x00}), (Bytes{0x90, 0x02}));
  Bytes big = {0x10, 0x01, 0x00, 0x00, 124, 248};
  big.resize(big.size() + 248, 0);
  EXPECT_EQ(handle(big), (Bytes{0x90, 0x02}));
}

TEST_F(Handler, WriteMultipleCanBeSwitchedOff) {
  options.write_multiple_registers = false;
  EXPECT_EQ(handle({0x10, 0x01, 0x00, 0x00, 0x01, 0x02, 0x12, 0x34}), (Bytes{0x90, 0x01}));
}

TEST_F(Handler, DeviceIdentificationBasic) {
  options.identity.vendor_name = "V";
  options.identity.product_code = "PC";
  options.identity.revision = "1.2";
  EXPECT_EQ(handle({0x2B, 0x0E, 0x01, 0x00}),
            (Bytes{0x2B, 0x0E, 0x01, 0x82, 0x00, 0x00, 0x03, 0x00, 1, 'V', 0x01, 2, 'P', 'C', 0x02, 3, '1', '.', '2'}));
}

TEST_F(Handler, DeviceIdentificationIndividualAndErrors) {
  options.identity.product_name = "Bridge";
  EXPECT_EQ(handle({0x2B, 0x0E, 0x04, 0x04}), (Bytes{0x2B, 0x0E, 0x04, 0x82, 0x00, 0x00, 0x01, 0x04, 6, 'B', 'r', 'i',
                                                     'd', 'g', 'e'}));
  EXPECT_EQ(handle({0x2B, 0x0E, 0x04, 0x80}), (Bytes{0xAB, 0x02}));  // no such object
  EXPECT_EQ(handle({0x2B, 0x0E, 0x05, 0x00}), (Bytes{0xAB, 0x03}));  // no such read code
  EXPECT_EQ(handle({0x2B, 0x0D, 0x01, 0x00}), (Bytes{0xAB, 0x01}));  // CANopen MEI type
  EXPECT_EQ(handle({0x2B, 0x0E, 0x01}), (Bytes{0xAB, 0x03}));
  options.device_identification = false;
  EXPECT_EQ(handle({0x2B, 0x0E, 0x01, 0x00}), (Bytes{0xAB, 0x01}));
}

TEST_F(Handler, DeviceIdentificationStreamRestartsAtAnUnknownObject) {
  const auto from_unknown = handle({0x2B, 0x0E, 0x01, 0x05});
  const auto from_zero = handle({0x2B, 0x0E, 0x01, 0x00});
  EXPECT_EQ(from_unknown, from_zero);
}

TEST(ExceptionOf, TellsExceptionsFromAnswers) {
  EXPECT_EQ(exception_of(Bytes{0x84, 0x02}), ExceptionCode::illegal_data_address);
  EXPECT_EQ(exception_of(Bytes{0x04, 0x02, 0x00, 0x01}), ExceptionCode::none);
}

TEST(Mbap, SeedQueryIsOneCompleteAdu) {
  const Bytes query = {0x12, 0x34, 0x00, 0x00, 0x00, 0x06, 0x01, 0x04, 0x00, 0x11, 0x00, 0x02};
  const auto adu = parse_tcp_adu(query);
  ASSERT_EQ(adu.status, TcpAdu::Status::complete);
  EXPECT_EQ(adu.header.transaction_id, 0x1234);
  EXPECT_EQ(adu.header.unit_id, 1);
  EXPECT_EQ(adu.size, query.size());
  EXPECT_EQ(Bytes(adu.pdu.begin(), adu.pdu.end()), (Bytes{0x04, 0x00, 0x11, 0x00, 0x02}));
}

TEST(Mbap, EveryPrefixNeedsMore) {
  const Bytes query = {0x12, 0x34, 0x00, 0x00, 0x00, 0x06, 0x01, 0x04, 0x00, 0x11, 0x00, 0x02};
  for (std::size_t n = 0; n < query.size(); ++n)
    EXPECT_EQ(parse_tcp_adu(std::span(query.data(), n)).status, TcpAdu::Status::need_more) << n;
}

TEST(Mbap, BadHeadersAreBad) {
  EXPECT_EQ(parse_tcp_adu(Bytes{0, 1, 0, 1, 0, 6, 1, 4}).status, TcpAdu::Status::bad_header);  // protocol 1
  EXPECT_EQ(parse_tcp_adu(Bytes{0, 1, 0, 0, 0, 1, 1}).status, TcpAdu::Status::bad_header);     // length 1
  EXPECT_EQ(parse_tcp_adu(Bytes{0, 1, 0, 0, 0, 255, 1}).status, TcpAdu::Status::bad_header);   // length 255
}

TEST(Mbap, WriteProducesTheSeedResponse) {
  const Bytes pdu = {0x04, 0x04, 0x00, 0x50, 0x7F, 0xFF};
  Bytes out(mbap_header_size + pdu.size());
  EXPECT_EQ(write_tcp_adu(0x1234, 1, pdu, out), out.size());
  EXPECT_EQ(out, (Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x07, 0x01, 0x04, 0x04, 0x00, 0x50, 0x7F, 0xFF}));
}

TEST(Mbap, HeaderForAPduBuiltInPlace) {
  Bytes out(mbap_header_size, 0xEE);
  const Bytes pdu = {0x04, 0x04, 0x00, 0x50, 0x7F, 0xFF};
  out.insert(out.end(), pdu.begin(), pdu.end());
  EXPECT_EQ(write_mbap_header(0x1234, 1, pdu.size(), out), mbap_header_size);
  EXPECT_EQ(out, (Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x07, 0x01, 0x04, 0x04, 0x00, 0x50, 0x7F, 0xFF}));
}

}  // namespace
}  // namespace unima::modbus
