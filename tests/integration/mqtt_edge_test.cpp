// MQTT's leading edge (SPEC §12, issue 32's propagation target) and reporting (SPEC §21)
// against a real broker: a bank's change goes at once when its last document is
// min_interval old or more, and one that comes sooner goes when it is, with the latest
// state; a move within its deadband is no change, a null always is; each bank goes in
// full every max_interval; a document's `time` is when its newest value was measured, a
// re-send keeps it, and a scaled value is written with its fraction. Asserted by the
// documents a subscriber gets, their `time` fields and what must have come before
// something the test saw (a lower bound, never a deadline): the telegrams are paced by
// Modbus reads that see them, the quiet moments by sleeps that are longer than the cap.

#include <optional>
#include <thread>

#include <nlohmann/json.hpp>

#include "platform/utc_time.hpp"
#include "tests/integration/bridge_fixture.hpp"
#include "tests/support/peers/mqtt_broker.hpp"
#include "tests/support/peers/mqtt_subscription.hpp"

namespace unima::test {
namespace {

using namespace std::chrono_literals;
using test_support::Broker;
using test_support::payloads;
using test_support::Subscription;

constexpr auto d1_topic = "fleet/site-17/D1";
constexpr int engine_speed_address = 0x0012;  // D1+0x01 in the fixture's layout

/// The system clock as a document's `time` writes it (microseconds).
std::chrono::system_clock::time_point now_in_stamps() {
  return std::chrono::floor<std::chrono::microseconds>(std::chrono::system_clock::now());
}

struct Document {
  int engine_speed;
  std::chrono::system_clock::time_point time;
};

class MqttEdge : public BridgeTest {
 protected:
  void SetUp() override {
    BridgeTest::SetUp();
    broker = std::make_unique<Broker>(dir.path());
    ASSERT_TRUE(broker->start());
    config.extra += test_support::site_17_mqtt(*broker);  // period 60 s: no full round in a test
  }
  void feed_speed(Socket& feed, int speed) {
    feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":1,"values":[)" + std::to_string(speed) + "]}", engine_speed_address,
                  static_cast<std::uint16_t>(speed));
  }
  /// The D1 documents `subscription` got whose engine_speed is at least `from`, in order.
  static std::vector<Document> documents(const Subscription& subscription, int from) {
    std::vector<Document> found;
    for (const auto& payload : payloads(subscription.lines(), d1_topic)) {
      const auto document = nlohmann::json::parse(payload);
      if (!document["engine_speed"].is_number() || document["engine_speed"].get<int>() < from) continue;
      const auto time = platform::parse_utc_time(document["time"].get<std::string>());
      EXPECT_TRUE(time) << payload;
      found.push_back({document["engine_speed"].get<int>(), time.value_or(std::chrono::system_clock::time_point{})});
    }
    return found;
  }
  std::unique_ptr<Broker> broker;
};

// Two changes: the first after a quiet moment goes at once, alone; the second, fed as
// soon as Modbus shows the first, is within the first's 100 ms and goes when they are up.
// On a fixed 100 ms grid the two would mostly fall into one tick and make one document.
TEST_F(MqttEdge, AChangeAfterQuietGoesAloneAndTheNextWithin100msGoesWhenTheyAreUp) {
  start();
  auto feed = feed_client();
  Subscription subscription(*broker, dir.path() / "sub", d1_topic);
  feed_speed(feed, 1000);
  ASSERT_TRUE(eventually([&] { return !documents(subscription, 1000).empty(); }, 6000ms)) << daemon->log();
  std::this_thread::sleep_for(300ms);  // quiet: D1's last document is older than the cap

  const auto began = std::chrono::steady_clock::now();
  const auto fed_first = now_in_stamps();
  feed_speed(feed, 2001);
  const auto fed_second = now_in_stamps();
  feed_speed(feed, 2002);
  const auto fed_both = now_in_stamps();
  ASSERT_TRUE(eventually([&] {
    const auto got = documents(subscription, 2001);
    return !got.empty() && got.back().engine_speed == 2002;
  }, 6000ms)) << subscription.lines();
  // The second went no sooner than 100 ms after the first, which went after `began`.
  EXPECT_GE(std::chrono::steady_clock::now() - began, 100ms);
  std::this_thread::sleep_for(300ms);  // room for a document that should not come
  const auto got = documents(subscription, 2001);
  ASSERT_EQ(got.size(), 2u) << subscription.lines();
  EXPECT_EQ(got[0].engine_speed, 2001) << "the leading edge: the first change alone, at once";
  EXPECT_EQ(got[1].engine_speed, 2002) << "the latest state once the 100 ms are up";
  // SPEC §21: each document is timed when its value arrived, not when it went.
  EXPECT_GE(got[0].time, fed_first);
  EXPECT_LE(got[0].time, fed_second);
  EXPECT_GE(got[1].time, fed_second);
  EXPECT_LE(got[1].time, fed_both);
}

// A burst of changes: the first goes at once, the rest are coalesced — documents at least
// 100 ms apart, each with the state of its moment, the last one with the last value.
TEST_F(MqttEdge, ABurstGivesItsFirstValueAtOnceThenAtMostOneDocumentPer100ms) {
  start();
  auto feed = feed_client();
  Subscription subscription(*broker, dir.path() / "sub", d1_topic);
  feed_speed(feed, 1000);
  ASSERT_TRUE(eventually([&] { return !documents(subscription, 1000).empty(); }, 6000ms)) << daemon->log();
  std::this_thread::sleep_for(300ms);

  const auto began = std::chrono::steady_clock::now();
  constexpr int first = 3001, last = 3040;
  for (int speed = first; speed <= last; ++speed) feed_speed(feed, speed);
  ASSERT_TRUE(eventually([&] {
    const auto got = documents(subscription, first);
    return !got.empty() && got.back().engine_speed == last;
  }, 6000ms)) << subscription.lines();
  const auto seen = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(300ms);
  const auto got = documents(subscription, first);
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got.front().engine_speed, first) << subscription.lines();
  EXPECT_EQ(got.back().engine_speed, last);
  EXPECT_LT(got.size(), static_cast<std::size_t>(last - first + 1)) << "coalesced, not one per change";
  // 100 ms at least between two documents, the first after `began`, the last before `seen`.
  EXPECT_LE(got.size() - 1, static_cast<std::size_t>((seen - began) / 100ms)) << subscription.lines();
  for (std::size_t i = 1; i < got.size(); ++i) {
    EXPECT_GT(got[i].engine_speed, got[i - 1].engine_speed) << "in order, never a backlog";
    EXPECT_GT(got[i].time, got[i - 1].time) << "each timed by its newest telegram";
  }
}

// SPEC §21: a move within the deadband is no change — the next is measured from the value
// published, not from the last one seen — and a change to or from null always counts.
TEST_F(MqttEdge, ADeadbandHoldsBackSmallMovesAndANullAlwaysCounts) {
  config.extra += "report: { min_interval: 0ms, deadband: { D1.engine_speed: 5 } }\n";
  start();
  auto feed = feed_client();
  Subscription subscription(*broker, dir.path() / "sub", d1_topic);
  feed_speed(feed, 1500);
  ASSERT_TRUE(eventually([&] { return !documents(subscription, 1500).empty(); }, 6000ms)) << daemon->log();
  for (const int speed : {1503, 1504, 1506, 0x7FFF, 1507}) feed_speed(feed, speed);  // 0x7FFF: not measured
  const auto speeds = [&] {
    std::vector<std::optional<int>> found;  // of the documents from the first 1500 on; nullopt: null
    for (const auto& payload : payloads(subscription.lines(), d1_topic)) {
      const auto speed = nlohmann::json::parse(payload)["engine_speed"];
      if (speed == 1500 && found.empty()) found.emplace_back(1500);
      else if (!found.empty()) found.push_back(speed.is_null() ? std::nullopt : std::optional<int>(speed.get<int>()));
    }
    return found;
  };
  ASSERT_TRUE(eventually([&] {
    const auto got = speeds();
    return !got.empty() && got.back() == 1507;
  }, 6000ms)) << subscription.lines();
  EXPECT_EQ(speeds(), (std::vector<std::optional<int>>{1500, 1506, std::nullopt, 1507}))
      << "1503 and 1504 are within 5 of 1500; 1507 is 1 from 1506, but from null" << subscription.lines();

  // A scaled value keeps its fraction when it is whole, so its type never flips.
  feed_and_wait(feed, R"({"addr":5,"slot":0,"offset":33,"values":[850]})", 0x0011 + 33, 850);
  EXPECT_TRUE(eventually([&] {
    const auto lines = subscription.lines();
    return lines.find("\"oil_temperature\":85.0,") != std::string::npos ||
           lines.find("\"oil_temperature\":85.0}") != std::string::npos;
  }, 6000ms)) << subscription.lines();
}

// SPEC §21: every max_interval the document goes again, and a re-send without a new
// telegram keeps the time its values were measured at.
TEST_F(MqttEdge, AResendAtMaxIntervalKeepsTheTimeOfItsMeasurement) {
  config.extra += "report: { max_interval: 1s }\n";
  start();
  auto feed = feed_client();
  Subscription subscription(*broker, dir.path() / "sub", d1_topic);
  const auto began = std::chrono::steady_clock::now();
  const auto before = now_in_stamps();
  feed_speed(feed, 1500);
  const auto after = now_in_stamps();
  const auto sent = [&] {
    std::vector<std::string> found;
    for (const auto& payload : payloads(subscription.lines(), d1_topic))
      if (nlohmann::json::parse(payload)["engine_speed"] == 1500) found.push_back(payload);
    return found;
  };
  ASSERT_TRUE(eventually([&] { return sent().size() >= 3; }, 6000ms)) << subscription.lines();
  // The first went after `began`, each re-send a max_interval after the one before.
  EXPECT_GE(std::chrono::steady_clock::now() - began, 2s);
  const auto got = sent();
  EXPECT_EQ(got[1], got[0]) << "the same document, its time too";
  EXPECT_EQ(got[2], got[0]);
  const auto time = platform::parse_utc_time(nlohmann::json::parse(got[0])["time"].get<std::string>());
  ASSERT_TRUE(time);
  EXPECT_GE(*time, before) << "when the telegram came, not when the document went";
  EXPECT_LE(*time, after);
}

}  // namespace
}  // namespace unima::test
