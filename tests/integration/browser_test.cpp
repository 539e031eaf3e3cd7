// The front page in a real browser (SPEC §13): headless Chromium, driven over WebDriver
// by tests/integration/browser/page_in_chromium.py, loads the daemon's page and the test
// checks its DOM — a value fed a moment before in its unit, D1 on line, values that have
// none saying why, and a value fed while the page is open, which only the live feed
// (/api/events) can bring.

#include <algorithm>
#include <chrono>
#include <future>
#include <map>
#include <thread>

#include <nlohmann/json.hpp>

#include "tests/integration/bridge_fixture.hpp"

namespace unima::test {
namespace {

// A bridge with its page on a free port, and Chromium opening it in the background.
class PageTest : public BridgeTest {
 protected:
  void start_with_page() {
    http_port = free_port();
    config.extra += "http: { listen: 127.0.0.1, port: " + std::to_string(http_port) + " }\n";
    // Chromium may take longer to start on a loaded machine than the default offline_after
    // (5 s): D1 must stay on line with the one telegram fed before the page opens.
    config.unimabus_extra = "  offline_after: 10min\n";
    start();
    ASSERT_TRUE(wait_for_port(http_port)) << daemon->log();
  }

  /// Opens the page, waits until it shows `expectations` (page_in_chromium.py's
  /// --expect/--online arguments), then for `later` while the test feeds them.
  void open_page(const std::string& expectations, const std::string& later) {
    const auto command = std::string(UNIMA_SOURCE_DIR) + "/tests/integration/browser/page_in_chromium.py --url http://127.0.0.1:" +
                         std::to_string(http_port) + "/ " + expectations + " --ready-file " + ready_file.string() +
                         " --then " + later + " --timeout 30 2>&1";
    browser = std::async(std::launch::async, [this, command] { return run(command); });
  }

  bool page_shows_first_expectations() {
    return eventually([&] { return std::filesystem::exists(ready_file); }, std::chrono::seconds(40));
  }

  std::uint16_t http_port = 0;
  std::filesystem::path ready_file = dir.path() / "page-ready";
  std::future<CommandResult> browser;
};

TEST_F(PageTest, ThePageInChromiumShowsAFedValueD1OnLineAndLaterValuesLive) {
  ASSERT_NO_FATAL_FAILURE(start_with_page());
  auto feed = feed_client();
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":1,"values":[1234]})", 0x0012, 1234);
  // 0x0032 is D1's oil_temperature, never fed; 0x0100 is W+0, never written.
  open_page("--online D1 --expect 0x0012=1234 --expect 0x0032=32767 --expect 0x0100=32767", "0x0012=4321");
  // The page showed the first value: feed the next while it stays open.
  const bool page_ready = page_shows_first_expectations();
  if (page_ready) feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":1,"values":[4321]})", 0x0012, 4321);
  const auto result = browser.get();
  ASSERT_TRUE(page_ready) << result.output;
  ASSERT_EQ(result.status, 0) << result.output;
  const auto shown = nlohmann::json::parse(result.output.substr(result.output.rfind("{\"ok\"")));
  EXPECT_EQ(shown["feed"], "live") << result.output;
  EXPECT_EQ(shown["online"]["D1"], true) << result.output;
  EXPECT_EQ(shown["online"]["D4"], false) << result.output;
  // engine_speed, min-1 (seed 004's table for UNIGEN CHP): shown in its unit, grouped.
  EXPECT_EQ(shown["values"]["0x0012"]["text"], "4,321 min-1") << result.output;
  // SPEC §17: why a value has none, in words.
  EXPECT_EQ(shown["values"]["0x0032"]["text"], "not measured") << result.output;
  EXPECT_EQ(shown["values"]["0x0100"]["text"], "not set") << result.output;
}

// What the page shows of the values (SPEC §17) and the capture indicators (SPEC §8), read
// from its DOM: why a value has none in words, a byte pair as two values in their units, a
// 32-bit pair as one, no reserves, an unsigned value above 32767, bit words in hex, and
// the indicators green for a read and red for a write.
class PageValuesTest : public PageTest {
 protected:
  void SetUp() override {
    PageTest::SetUp();
    // D2 is a UIS at address 6; D4 a UVR at address 9 that never speaks: off-line.
    config.devices = "{ D1: { type: unigen-chp, address: 5 }, D2: { type: uis, address: 6 }, D4: { type: uvr, address: 9 } }";
    config.extra += "mapping: { A: [ D1.engine_speed ] }\n";  // A+0x01.. not mapped
    config.monitor_section = "monitor:\n  indicators: [ { address: 1, register: 0x0101 }, { address: 1, register: 0x0012 } ]\n";
  }

  /// What the page showed, with every value cell by its key, once `expectations` held.
  nlohmann::json page_shows(const std::string& expectations) {
    const auto command = std::string(UNIMA_SOURCE_DIR) + "/tests/integration/browser/page_in_chromium.py --url http://127.0.0.1:" +
                         std::to_string(http_port) + "/ " + expectations + " --every-value --timeout 30 2>&1";
    const auto result = run(command);
    EXPECT_EQ(result.status, 0) << result.output;
    const auto start = result.output.rfind("{\"ok\"");
    if (start == std::string::npos) return nlohmann::json::object();
    return nlohmann::json::parse(result.output.substr(start), nullptr, false);
  }
};

TEST_F(PageValuesTest, ThePageShowsEachValueAsTheSeedMeansItAndWhyAValueHasNone) {
  ASSERT_NO_FATAL_FAILURE(start_with_page());
  auto feed = feed_client();
  // D1: status 0x450E (named bits), engine_speed 41234, operating_hours 26 × 65536 + 100 s;
  // status_word 0x250D (no named bits).
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":15,"values":[9485]})", 0x0011 + 0x0F, 9485);
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":0,"values":[17678,41234,100,26]})", 0x0012, 41234);
  // D2 (0x1200): knock_rank_1 = cylinder 3, level 128 (100 %); knock_rank_2 = cylinder 4, level 255.
  feed_and_wait(feed, R"({"addr":6,"slot":0,"offset":8,"values":[32771,65284]})", 0x1209, 65284);
  ModbusClient client(config.modbus_port);
  ASSERT_TRUE(client.write(0x0101, 0x1234));       // indicator 1: a write
  ASSERT_TRUE(client.read_input(0x0012, 1));       // indicator 2: a read
  ASSERT_TRUE(client.write(0x3010, 0x0021));       // X: bits 0 and 5

  const auto shown = page_shows("--online D1 --online D2 --expect 0x0012=41234 --expect 0x1208=32771 "
                                "--expect 0x3010=33 --indicator 1=write --indicator 2=read");
  ASSERT_TRUE(shown.contains("keys")) << shown.dump(1);
  const auto& keys = shown["keys"];
  const auto text = [&](const std::string& key) {
    return keys.contains(key) ? keys[key]["text"].get<std::string>() : "(no cell " + key + ")";
  };
  // The four reasons a value has none, in words.
  EXPECT_EQ(text("D1/oil_temperature"), "not measured");  // D1 on-line, never fed
  EXPECT_EQ(text("D4/generator_voltage"), "off-line");    // configured, silent
  EXPECT_EQ(text("W/w_00"), "not set");                   // never written
  EXPECT_EQ(text("A/a_01"), "not mapped");                // an A entry without a source
  // A byte pair: two values, each in its unit; a byte of 255 is not measured.
  EXPECT_EQ(text("D2/knock_rank_1.cylinder"), "3");
  EXPECT_EQ(text("D2/knock_rank_1.level"), "100 %");
  EXPECT_EQ(text("D2/knock_rank_2.cylinder"), "4");
  EXPECT_EQ(text("D2/knock_rank_2.level"), "not measured");
  // A 32-bit pair: one value, not two halves; a counter of seconds read in hours, the
  // seconds in its title, grouped as the reader's language groups them.
  EXPECT_EQ(text("D1/operating_hours"), "473.3 h");
  EXPECT_NE(keys["D1/operating_hours"]["title"].get<std::string>().find("1,704,036 s"), std::string::npos) << keys["D1/operating_hours"];
  // Unsigned above 32767.
  EXPECT_EQ(text("D1/engine_speed"), "41,234 min-1");
  // A number the seed's table gives no unit says so in its title.
  EXPECT_NE(keys["D1/status.state"]["title"].get<std::string>().find("no unit in the device table"), std::string::npos)
      << keys["D1/status.state"];
  EXPECT_EQ(keys["D1/engine_speed"]["title"], "0x0012 = 41234") << "a value in its unit needs no note";
  // By register, the last cell of each: engine_speed, and the byte pair's level.
  EXPECT_EQ(shown["values"]["0x0012"]["text"], "41,234 min-1") << shown["values"];
  EXPECT_EQ(shown["values"]["0x1208"]["text"], "100 %") << shown["values"];
  // Bit words in hex, whether the seed names their bits (status) or not (status_word); a
  // field of several bits is a number.
  EXPECT_EQ(text("D1/status"), "0x450E");
  EXPECT_EQ(text("D1/status_word"), "0x250D");
  EXPECT_EQ(text("D1/status.state"), "14");
  // X is a bit word too: the word in hex, each of its sixteen bits on or off.
  EXPECT_EQ(text("X/x"), "0x0021");
  EXPECT_EQ(text("X/x.0"), "on");
  EXPECT_EQ(text("X/x.5"), "on");
  EXPECT_EQ(text("X/x.4"), "off");
  EXPECT_EQ(text("X/x.15"), "off");
  for (const auto& [key, cell] : keys.items()) {
    EXPECT_FALSE(key.ends_with("_high") || key.ends_with("_low")) << key;  // no half of a pair
    EXPECT_EQ(cell["text"].get<std::string>().find("32767"), std::string::npos) << key << ": " << cell;
  }
  // D2's reserves (+0x06, +0x0B, +0x0E) have no row.
  const auto& addresses = shown["addresses"];
  for (const auto* reserve : {"0x1206", "0x120B", "0x120E"})
    EXPECT_TRUE(std::find(addresses.begin(), addresses.end(), reserve) == addresses.end()) << reserve << " is listed";

  // The capture indicators: red for a write, green for a read (seed 004 §2).
  ASSERT_EQ(shown["indicators"].size(), 2u) << shown["indicators"];
  EXPECT_NE(shown["indicators"][0]["class"].get<std::string>().find("access-write"), std::string::npos) << shown["indicators"];
  EXPECT_EQ(shown["indicators"][0]["colour"], "rgb(210, 47, 47)") << shown["indicators"];
  EXPECT_NE(shown["indicators"][1]["class"].get<std::string>().find("access-read"), std::string::npos) << shown["indicators"];
  EXPECT_EQ(shown["indicators"][1]["colour"], "rgb(31, 157, 69)") << shown["indicators"];
}

// On a phone's width (390 px): the monitor colours each line by its transaction's state
// (an Err02 unlike a Done) and wraps a long line instead of cutting it at the edge; the
// Czech labels of the registers stay.
TEST_F(PageTest, OnAPhoneTheMonitorColoursLinesByStateWrapsThemAndTheLabelsStay) {
  ASSERT_NO_FATAL_FAILURE(start_with_page());
  auto feed = feed_client();
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":1,"values":[1234]})", 0x0012, 1234);
  open_page("--online D1 --expect 0x0012=1234 --window 390,844", "0x0012=1234 --line Done --line Err02");
  const bool page_ready = page_shows_first_expectations();
  if (page_ready) {
    ModbusClient client(config.modbus_port);
    EXPECT_TRUE(client.read_input(0x0011, 64));        // Done: a long line, 64 registers of hex
    EXPECT_FALSE(client.read_input(0x0011 + 0x40, 1));  // past D1: Err02
  }
  const auto result = browser.get();
  ASSERT_TRUE(page_ready) << result.output;
  ASSERT_EQ(result.status, 0) << result.output;
  const auto shown = nlohmann::json::parse(result.output.substr(result.output.rfind("{\"ok\"")));
  EXPECT_LE(shown["width"].get<int>(), 390) << result.output;
  std::map<std::string, std::string> colour;
  for (const auto& line : shown["monitor"]) colour[line["state"].is_null() ? "" : line["state"].get<std::string>()] = line["colour"];
  ASSERT_TRUE(colour.contains("Done") && colour.contains("Err02")) << result.output;
  EXPECT_NE(colour["Done"], colour["Err02"]) << result.output;
  EXPECT_EQ(colour["Err02"], "rgb(255, 138, 138)") << result.output;
  EXPECT_EQ(shown["monitor_cut"], false) << "a line cut at the box's right edge: " << result.output;
  EXPECT_GT(shown["labels"]["with_text"].get<int>(), 10) << result.output;
  EXPECT_EQ(shown["labels"]["shown"], shown["labels"]["with_text"]) << "labels hidden at 390 px: " << result.output;
}

// The daemon restarts while the page is open: the page reconnects by itself and shows
// what is fed after the restart.
TEST_F(PageTest, ThePageInChromiumComesBackAfterTheDaemonRestarts) {
  ASSERT_NO_FATAL_FAILURE(start_with_page());
  {
    auto feed = feed_client();
    feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":1,"values":[1111]})", 0x0012, 1111);
  }
  open_page("--expect 0x0012=1111", "0x0012=2222");
  const bool page_ready = page_shows_first_expectations();
  if (page_ready) {
    daemon->terminate();
    daemon.reset();
    start();
    auto feed = feed_client();
    feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":1,"values":[2222]})", 0x0012, 2222);
  }
  const auto result = browser.get();
  ASSERT_TRUE(page_ready) << result.output;
  EXPECT_EQ(result.status, 0) << result.output;
}

}  // namespace
}  // namespace unima::test
