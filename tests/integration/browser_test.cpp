// The front page in a real browser (SPEC §13): headless Chromium, driven over WebDriver
// by tests/integration/browser/page_in_chromium.py, loads the daemon's page and the test
// checks its DOM — a value fed a moment before in its unit, D1 on line, values that have
// none saying why, and a value fed while the page is open, which only the live feed
// (/api/events) can bring.

#include <chrono>
#include <future>
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
  // engine_speed, min-1 (seed 004's table for UNIGEN CHP): shown in its unit.
  EXPECT_EQ(shown["values"]["0x0012"]["text"], "4321 min-1") << result.output;
  // SPEC §17: why a value has none, in words.
  EXPECT_EQ(shown["values"]["0x0032"]["text"], "not measured") << result.output;
  EXPECT_EQ(shown["values"]["0x0100"]["text"], "not set") << result.output;
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
