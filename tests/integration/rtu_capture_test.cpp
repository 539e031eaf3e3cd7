// Capture blocks on the RTU line (MBS_RegC, seed 004 §7.1, SPEC §4): the test plays a
// third-party master and the foreign slave 3 on the same line; the bridge takes the
// value of register 0x0202 of device 3 into user output 2 (C+0x01), publishes it to
// UnimaBUS, and never answers.

#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "tests/integration/rtu_fixture.hpp"

namespace unima::test {
namespace {

constexpr std::uint16_t not_measured = 0x7FFF;

class RtuCapture : public RtuTest {
 protected:
  void SetUp() override {
    RtuTest::SetUp();
    start_rtu("blocks:\n  - { type: capture, device: 3, register: 0x0202, output: 2 }\n");
    feed = std::make_unique<Socket>(feed_client());
  }
  std::uint16_t user_output_2() {
    ModbusClient tcp(config.modbus_port);
    const auto value = tcp.read_input(0x1021, 1);  // C+0x01 at the default base
    return value ? (*value)[0] : 0;
  }
  std::unique_ptr<Socket> feed;
};

TEST_F(RtuCapture, AForeignWriteIsCapturedAndNotAnswered) {
  const auto write = rtu_adu(3, {0x06, 0x02, 0x02, 0x00, 0x2A});
  line->write(write);
  line->write(write);  // slave 3 echoes it
  EXPECT_TRUE(feed->wait_for_line(R"({"bank":"C","offset":1,"value":42})"));
  EXPECT_EQ(user_output_2(), 42);
  expect_next_reply_is_to_a_read_of_w(not_measured);
}

TEST_F(RtuCapture, AForeignReadIsCapturedFromTheSlavesResponse) {
  line->write(rtu_adu(3, {0x04, 0x02, 0x00, 0x00, 0x04}));  // 0x0200..0x0203
  line->write(rtu_adu(3, {0x04, 0x08, 0x00, 0x01, 0x00, 0x02, 0x01, 0x2C, 0x00, 0x04}));
  EXPECT_TRUE(feed->wait_for_line(R"({"bank":"C","offset":1,"value":300})"));
  // Function 3 too (an extension of the seed's function 4).
  line->write(rtu_adu(3, {0x03, 0x02, 0x02, 0x00, 0x01}));
  line->write(rtu_adu(3, {0x03, 0x02, 0x01, 0x2D}));
  EXPECT_TRUE(feed->wait_for_line(R"({"bank":"C","offset":1,"value":301})"));
  expect_next_reply_is_to_a_read_of_w(not_measured);
}

TEST_F(RtuCapture, OtherDevicesRegistersAndBrokenFramesAreNotCaptured) {
  line->write(rtu_adu(4, {0x06, 0x02, 0x02, 0x00, 0x01}));  // another device
  line->write(rtu_adu(3, {0x06, 0x02, 0x03, 0x00, 0x02}));  // another register
  auto broken = rtu_adu(3, {0x06, 0x02, 0x02, 0x00, 0x03});
  broken[5] ^= 0x10;                                        // a bad CRC
  line->write(broken);
  line->write(rtu_adu(3, {0x04, 0x02, 0x02, 0x00, 0x01}));  // a read answered with an exception
  line->write(rtu_adu(3, {0x84, 0x02}));
  line->write(rtu_adu(3, {0x06, 0x02, 0x02, 0x00, 0x05}));  // and then the one that counts
  // The first capture the feed client sees is the last write: none of the others set it.
  std::optional<std::string> first;
  ASSERT_TRUE(eventually([&] {
    while (auto line_read = feed->read_line(100ms))
      if (line_read->starts_with(R"({"bank":"C","offset":1,)")) {
        first = line_read;
        return true;
      }
    return false;
  }));
  EXPECT_EQ(*first, R"({"bank":"C","offset":1,"value":5})");
  expect_next_reply_is_to_a_read_of_w(not_measured);
}

// 1200 baud (t3.5 = 29 ms): a test process held up between two bytes is no silence.
class RtuCaptureSlowLine : public RtuCapture {
 protected:
  void SetUp() override {
    baud = 1200;
    RtuCapture::SetUp();
  }
};

TEST_F(RtuCaptureSlowLine, AFrameSplitAtEveryByteIsCapturedOnce) {
  const auto write = rtu_adu(3, {0x06, 0x02, 0x02, 0x01, 0x00});
  for (std::uint8_t b : write) line->write(Bytes{b});
  EXPECT_TRUE(feed->wait_for_line(R"({"bank":"C","offset":1,"value":256})"));
  EXPECT_EQ(user_output_2(), 256);
}

}  // namespace
}  // namespace unima::test

namespace unima::test {
namespace {

std::string hex_of(const Bytes& bytes) {
  std::string out;
  for (auto b : bytes) out += fmt::format("{}{:02X}", out.empty() ? "" : " ", b);
  return out;
}

// Seed §5.3 note 3: a foreign slave's answer shorter than 5 bytes or of another function
// is Err04 on its query's monitor line, with those bytes as the Response, and sets C+0x13
// bit 15; capture blocks take nothing from it.
class RtuForeignErrors : public RtuTest {
 protected:
  void SetUp() override {
    RtuTest::SetUp();
    log = dir.path() / "monitor.log";
    config.monitor_section = "monitor:\n  file: " + log.string() + "\n";
    start_rtu("blocks:\n  - { type: capture, device: 3, register: 0x0202, output: 2 }\n");
  }
  /// The monitor line whose query is `query`, once it is written.
  std::string line_of(const Bytes& query) {
    const auto pdu = hex_of(Bytes(query.begin() + 1, query.end() - 2));
    std::string found;
    EXPECT_TRUE(eventually([&] {
      std::istringstream in(read_file(log));
      for (std::string l; std::getline(in, l);)
        if (l.find(" rtu ") != std::string::npos && l.find("PDU=" + pdu + " ") != std::string::npos) found = l;
      return !found.empty();
    })) << read_file(log);
    return found;
  }
  /// The foreign master asks `query`, slave 3 answers `answer`: one Err04 line with that
  /// answer, the error bit set, and the line goes on.
  void expect_err04(const Bytes& query, const Bytes& answer) {
    line->write(query);
    line->write(answer);
    const auto monitored = line_of(query);
    EXPECT_NE(monitored.find("State=Err04"), std::string::npos) << monitored;
    EXPECT_NE(monitored.find("Response=" + hex_of(answer)), std::string::npos) << monitored;
    EXPECT_TRUE(error_bit_set());
    expect_next_reply_is_to_a_read_of_w(not_measured);
  }
  std::filesystem::path log;
};

TEST_F(RtuForeignErrors, AnAnswerOfAnotherFunctionIsErr04OnItsQuerysLine) {
  // Function 3 to a function-4 query.
  expect_err04(rtu_adu(3, {0x04, 0x02, 0x02, 0x00, 0x01}), rtu_adu(3, {0x03, 0x02, 0x01, 0x2C}));
  ModbusClient tcp(config.modbus_port);
  EXPECT_EQ(tcp.read_input(0x1021, 1), std::vector<std::uint16_t>{not_measured});  // nothing captured
}

TEST_F(RtuForeignErrors, AnAnswerShorterThanFiveBytesIsErr04OnItsQuerysLineAndNoOtherLine) {
  expect_err04(rtu_adu(3, {0x04, 0x02, 0x02, 0x00, 0x02}), rtu_adu(3, {0x04}));  // 4 bytes
  EXPECT_EQ(read_file(log).find("State=Err03"), std::string::npos) << read_file(log);
}

}  // namespace
}  // namespace unima::test

namespace unima::test {
namespace {

// SPEC §8, as on the hardware: the Modbus LED shows what the bridge sends — in slave mode
// its own responses, lit 100 ms after each — and not the foreign traffic it only hears.
class RtuModbusLed : public RtuCapture {
 protected:
  nlohmann::json status() const {
    const auto r = run(std::string(UNIMA_BRIDGE_CLI) + " status --json --socket " + config.status_socket);
    EXPECT_EQ(r.status, 0) << r.output;
    return nlohmann::json::parse(r.output, nullptr, false);
  }
};

TEST_F(RtuModbusLed, StaysDarkForTrafficTheBridgeOnlyHearsAndLightsForItsOwnAnswers) {
  for (std::uint8_t n = 1; n <= 3; ++n) {
    const auto write = rtu_adu(3, {0x06, 0x02, 0x02, 0x00, n});
    line->write(write);
    line->write(write);  // slave 3 echoes it
    // Captured and published: the bridge heard the exchange a moment ago.
    ASSERT_TRUE(feed->wait_for_line(fmt::format(R"({{"bank":"C","offset":1,"value":{}}})", n)));
    const auto heard = status();
    EXPECT_FALSE(heard["modbus"]["active"].get<bool>()) << heard.dump();
    EXPECT_EQ(heard["modbus"]["frames"], 0) << heard.dump();
  }
  // Its own answer lights the LED for 100 ms: asked again until a status lands in one.
  EXPECT_TRUE(eventually([&] {
    expect_next_reply_is_to_a_read_of_w(not_measured);
    return status()["modbus"]["active"] == true;
  })) << status().dump();
  EXPECT_GE(status()["modbus"].value("frames", 0), 1);
}

}  // namespace
}  // namespace unima::test
