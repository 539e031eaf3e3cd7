// The master's codec: the seeds' frames byte for byte (seed 000 §3.1–§3.2, seed 002 §6 —
// their CRCs are correct, so they are test vectors), the check of responses (seed 004 §8
// error states), and values: DINT, DWORD, REAL in either word order, scaling, bits.

#include <gtest/gtest.h>

#include <cmath>

#include "modbus/rtu/crc16.hpp"
#include "master/master_codec.hpp"
#include "master/master_value.hpp"

namespace unima::master {
using namespace unima::modbus;
namespace {

Bytes hex(std::string_view text) {
  Bytes out;
  for (std::size_t i = 0; i < text.size(); i += 3) out.push_back(static_cast<std::uint8_t>(std::stoul(std::string(text.substr(i, 2)), nullptr, 16)));
  return out;
}

Bytes read_frame(std::uint8_t address, std::uint8_t fn, std::uint16_t first, std::uint16_t count) {
  return rtu_frame(address, read_request_pdu(fn, first, count));
}

MasterBlock block(MasterBlock::Kind kind, std::uint8_t fn, std::uint16_t reg, std::uint16_t count, ValueType type) {
  MasterBlock b;
  b.kind = kind;
  b.function = fn;
  b.reg = reg;
  b.count = count;
  b.type = type;
  return b;
}

Bytes write_frame(std::uint8_t address, std::uint8_t fn, std::uint16_t first, std::vector<std::uint16_t> values) {
  return rtu_frame(address, write_request_pdu(fn, first, values));
}

TEST(MasterCodec, Sic184V3SeedFrames) {
  // §3.1: reading input IN1 (5000) as the seed does, eight inputs from 5000.
  EXPECT_EQ(read_frame(1, 2, 5000, 8), hex("01 02 13 88 00 08 FD 62"));
  // §3.1: setting output OUT2 (6001); the seed's frame writes 0x0000 (off).
  EXPECT_EQ(write_frame(1, 5, 6001, {0}), hex("01 05 17 71 00 00 98 65"));
  // §3.2: reading POS_ACT_REAL (1060), two registers.
  EXPECT_EQ(read_frame(1, 3, 1060, 2), hex("01 03 04 24 00 02 85 30"));
}

TEST(MasterCodec, StepperDriverSeedFrames) {
  // §6 (1): registers 40001 and 40002 (protocol 0 and 1), and the seed's response.
  EXPECT_EQ(read_frame(1, 3, 0, 2), hex("01 03 00 00 00 02 C4 0B"));
  const auto response = hex("01 03 04 00 B4 00 08 BB D3");
  const auto request_pdu = read_request_pdu(3, 0, 2);
  const auto checked = check_rtu_response(response, 1, request_pdu);
  ASSERT_EQ(checked.status, ResponseStatus::ok);
  EXPECT_EQ(response_values(checked.pdu, 3, 2), (std::vector<std::uint16_t>{180, 8}));
  // §6 (2): coil 00008 (protocol 7) on.
  EXPECT_EQ(write_frame(1, 5, 7, {1}), hex("01 05 00 07 FF 00 3D FB"));
  // §6 (3): register 40002 (protocol 1) = 4.
  EXPECT_EQ(write_frame(1, 6, 1, {4}), hex("01 06 00 01 00 04 D9 C9"));
  // §6 (4): 200 into 40010/40011 (protocol 9), low word first; and its response.
  std::vector<std::uint16_t> words(2);
  encode_value(ValueType::dword, WordOrder::low_first, 200, words);
  EXPECT_EQ(write_frame(1, 16, 9, words), hex("01 10 00 09 00 02 04 00 C8 00 00 B2 3B"));
  const auto write_pdu = write_request_pdu(16, 9, words);
  EXPECT_EQ(check_rtu_response(hex("01 10 00 09 00 02 91 CA"), 1, write_pdu).status, ResponseStatus::ok);
}

// The length rule itself is modbus::rtu_response_length's (rtu_framer_test.cpp); this pins
// the master's use of it: only the function asked for, or its exception, is framed by length.
TEST(MasterCodec, ExpectedResponseLengthFromItsFirstBytes) {
  EXPECT_EQ(expected_response_length(hex("01"), 3), std::nullopt);
  EXPECT_EQ(expected_response_length(hex("01 03"), 3), std::nullopt);
  EXPECT_EQ(expected_response_length(hex("01 03 04"), 3), 9u);
  EXPECT_EQ(expected_response_length(hex("01 02 01"), 2), 6u);
  EXPECT_EQ(expected_response_length(hex("01 83"), 3), 5u);
  EXPECT_EQ(expected_response_length(hex("01 06"), 6), 8u);
  EXPECT_EQ(expected_response_length(hex("01 10"), 16), 8u);
  EXPECT_EQ(expected_response_length(hex("01 04 02"), 3), std::nullopt);  // wrong function: only silence ends it
}

TEST(MasterCodec, RtuResponseFaults) {
  const auto request = read_request_pdu(3, 0, 2);
  auto good = hex("01 03 04 00 B4 00 08 BB D3");
  EXPECT_EQ(check_rtu_response({}, 1, request).status, ResponseStatus::timeout);
  EXPECT_EQ(check_rtu_response(hex("01 03 04 00"), 1, request).status, ResponseStatus::too_short);
  auto bad_crc = good;
  bad_crc.back() ^= 0xFF;
  EXPECT_EQ(check_rtu_response(bad_crc, 1, request).status, ResponseStatus::bad_crc);
  EXPECT_EQ(transaction_state(check_rtu_response(bad_crc, 1, request)), TransactionState::err03);
  EXPECT_EQ(check_rtu_response(good, 2, request).status, ResponseStatus::wrong_address);
  const auto wrong_function = rtu_frame(1, hex("04 04 00 B4 00 08"));
  EXPECT_EQ(check_rtu_response(wrong_function, 1, request).status, ResponseStatus::wrong_function);
  EXPECT_EQ(transaction_state(check_rtu_response(wrong_function, 1, request)), TransactionState::err04);
  const auto short_count = rtu_frame(1, hex("03 02 00 B4"));
  EXPECT_EQ(check_rtu_response(short_count, 1, request).status, ResponseStatus::bad_length);
  const auto exception = rtu_frame(1, hex("83 02"));
  const auto checked = check_rtu_response(exception, 1, request);
  EXPECT_EQ(checked.status, ResponseStatus::exception);
  EXPECT_EQ(checked.exception, ExceptionCode::illegal_data_address);
  EXPECT_EQ(transaction_state(checked), TransactionState::err02);
  EXPECT_TRUE(slave_answered(checked));
  const auto gateway = check_rtu_response(rtu_frame(1, hex("83 0B")), 1, request);
  EXPECT_EQ(transaction_state(gateway), TransactionState::err04);
  EXPECT_FALSE(slave_answered(gateway));  // the gateway answered, the slave behind it did not
  EXPECT_FALSE(slave_answered(check_rtu_response(bad_crc, 1, request)));
  const auto write = write_request_pdu(6, 1, std::vector<std::uint16_t>{4});
  EXPECT_EQ(check_rtu_response(rtu_frame(1, hex("06 00 01 00 05")), 1, write).status, ResponseStatus::wrong_echo);
}

TEST(MasterCodec, TcpResponse) {
  const auto request = read_request_pdu(3, 1060, 2);
  const auto good = hex("00 07 00 00 00 07 01 03 04 00 00 40 90");
  const auto checked = check_tcp_response(good, 1, request);
  ASSERT_EQ(checked.status, ResponseStatus::ok);
  EXPECT_EQ(response_values(checked.pdu, 3, 2), (std::vector<std::uint16_t>{0x0000, 0x4090}));
  EXPECT_EQ(check_tcp_response(hex("00 07 00 01 00 07 01 03 04 00 00 40 90"), 1, request).status, ResponseStatus::bad_frame);
  EXPECT_EQ(check_tcp_response(hex("00 07 00 00 00 07 01 03"), 1, request).status, ResponseStatus::too_short);
  EXPECT_EQ(check_tcp_response(good, 2, request).status, ResponseStatus::wrong_address);
}

TEST(MasterValue, Sic184DoubleWordsLowWordFirst) {
  // Seed 000 §4.1: Liczba_32_bit = RejestrX + Rejestr(X+1) << 16.
  const std::uint16_t pulses[] = {0xE100, 0x0000};  // 57600
  EXPECT_EQ(decode_value(ValueType::dint, WordOrder::low_first, pulses), 57600);
  const std::uint16_t negative[] = {0xFFFE, 0xFFFF};
  EXPECT_EQ(decode_value(ValueType::dint, WordOrder::low_first, negative), -2);
  EXPECT_EQ(decode_value(ValueType::dword, WordOrder::low_first, negative), 4294967294.0);
  const std::uint16_t high_first[] = {0x0001, 0x0000};
  EXPECT_EQ(decode_value(ValueType::dint, WordOrder::high_first, high_first), 65536);
  const std::uint16_t real[] = {0x0000, 0x4090};  // 4.5f = 0x40900000
  EXPECT_FLOAT_EQ(static_cast<float>(decode_value(ValueType::real, WordOrder::low_first, real)), 4.5f);
  std::uint16_t out[2];
  encode_value(ValueType::real, WordOrder::low_first, 4.5, out);
  EXPECT_EQ(out[0], 0x0000);
  EXPECT_EQ(out[1], 0x4090);
  encode_value(ValueType::dint, WordOrder::high_first, -2, out);
  EXPECT_EQ(out[0], 0xFFFF);
  EXPECT_EQ(out[1], 0xFFFE);
  encode_value(ValueType::dword, WordOrder::low_first, -5, out);  // clamped into the type
  EXPECT_EQ(out[0], 0);
  EXPECT_EQ(out[1], 0);
}

TEST(MasterValue, ScalingIntoBridgeRegisters) {
  EXPECT_EQ(to_bridge_register(4.5, 10, true), 45);
  EXPECT_EQ(to_bridge_register(-4.5, 10, true), static_cast<std::uint16_t>(-45));
  EXPECT_EQ(to_bridge_register(180, 0.1, false), 18);
  // 0x7FFF is "not measured": a signed value never lands on it.
  EXPECT_EQ(to_bridge_register(57600, 1, true), 0x7FFE);
  EXPECT_EQ(to_bridge_register(-1e9, 1, true), 0x8000);
  EXPECT_EQ(to_bridge_register(70000, 1, false), 0xFFFF);
  EXPECT_EQ(to_bridge_register(std::nan(""), 1, true), not_measured);
  EXPECT_DOUBLE_EQ(from_bridge_register(static_cast<std::uint16_t>(-45), true, 10), -4.5);
  EXPECT_DOUBLE_EQ(from_bridge_register(0xFFFF, false, 1), 65535);
}

TEST(MasterValue, PollOutputsFromAMergedResponse) {
  // One request 1020..1025 carrying POS_ACT_INT (dint) and VEL_ACT_INT.
  const std::vector<std::uint16_t> values{0x2710, 0x0000, 0x0000, 0x0000, 0xFFF6, 0xFFFF};
  auto position = block(MasterBlock::Kind::poll, 3, 1020, 2, ValueType::dint);
  auto velocity = block(MasterBlock::Kind::poll, 3, 1024, 2, ValueType::dint);
  velocity.scale = 10;
  EXPECT_EQ(poll_output(position, 1020, values), 10000);
  EXPECT_EQ(poll_output(velocity, 1020, values), static_cast<std::uint16_t>(-100));
  auto raw = block(MasterBlock::Kind::poll, 3, 1021, 1, ValueType::word);
  EXPECT_EQ(poll_output(raw, 1020, values), 0);
  // Bits: eight inputs from 5000, bit n = input 5000 + n.
  const std::vector<std::uint16_t> bits{1, 0, 1, 0, 0, 0, 0, 1};
  auto in = block(MasterBlock::Kind::poll, 2, 5000, 8, ValueType::bits);
  EXPECT_EQ(poll_output(in, 5000, bits), 0x85);
  auto in3 = block(MasterBlock::Kind::poll, 2, 5002, 1, ValueType::bits);
  EXPECT_EQ(poll_output(in3, 5000, bits), 1);
  const auto pdu = hex("02 01 85");
  EXPECT_EQ(response_values(pdu, 2, 8), bits);
}

TEST(MasterValue, SendValues) {
  auto copy = block(MasterBlock::Kind::send, 6, 1, 1, ValueType::word);
  EXPECT_EQ(send_values(copy, 0xABCD), (std::vector<std::uint16_t>{0xABCD}));
  auto coil = block(MasterBlock::Kind::send, 5, 7, 1, ValueType::bits);
  EXPECT_EQ(send_values(coil, 5), (std::vector<std::uint16_t>{1}));
  auto real = block(MasterBlock::Kind::send, 16, 1078, 2, ValueType::real);
  real.scale = 10;
  EXPECT_EQ(send_values(real, 25), (std::vector<std::uint16_t>{0x0000, 0x4020}));  // 2.5f
  auto dint = block(MasterBlock::Kind::send, 16, 9, 2, ValueType::dint);
  EXPECT_EQ(send_values(dint, static_cast<std::uint16_t>(-2)), (std::vector<std::uint16_t>{0xFFFE, 0xFFFF}));
}

TEST(MasterValue, Names) {
  for (auto t : {ValueType::bits, ValueType::word, ValueType::int16, ValueType::dint, ValueType::dword, ValueType::real})
    EXPECT_EQ(parse_value_type(value_type_name(t)), t);
  EXPECT_EQ(parse_value_type("float"), std::nullopt);
  EXPECT_EQ(parse_word_order("high_first"), WordOrder::high_first);
  EXPECT_EQ(parse_word_order("big"), std::nullopt);
}

}  // namespace
}  // namespace unima::master
