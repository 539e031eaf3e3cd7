// MQTT's leading edge (SPEC §12, issue 32's propagation target) against a real broker: a
// bank's change goes at once when its last document is 100 ms old or more, and one that
// comes sooner goes when those 100 ms are up, with the latest state. Asserted by the
// documents a subscriber gets and their `time` fields, never by timing the test: the
// telegrams are paced by Modbus reads that see them, the quiet moments by sleeps that are
// longer than the cap.

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

  feed_speed(feed, 2001);
  feed_speed(feed, 2002);
  ASSERT_TRUE(eventually([&] {
    const auto got = documents(subscription, 2001);
    return !got.empty() && got.back().engine_speed == 2002;
  }, 6000ms)) << subscription.lines();
  std::this_thread::sleep_for(300ms);  // room for a document that should not come
  const auto got = documents(subscription, 2001);
  ASSERT_EQ(got.size(), 2u) << subscription.lines();
  EXPECT_EQ(got[0].engine_speed, 2001) << "the leading edge: the first change alone, at once";
  EXPECT_EQ(got[1].engine_speed, 2002) << "the latest state once the 100 ms are up";
  // 95, not 100: the pacing runs on the steady clock, the stamps are the system clock read
  // just after (a fresh-clone CI saw 99.953 ms between two stamps).
  EXPECT_GE(got[1].time - got[0].time, 95ms) << subscription.lines();
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

  constexpr int first = 3001, last = 3040;
  for (int speed = first; speed <= last; ++speed) feed_speed(feed, speed);
  ASSERT_TRUE(eventually([&] {
    const auto got = documents(subscription, first);
    return !got.empty() && got.back().engine_speed == last;
  }, 6000ms)) << subscription.lines();
  std::this_thread::sleep_for(300ms);
  const auto got = documents(subscription, first);
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got.front().engine_speed, first) << subscription.lines();
  EXPECT_EQ(got.back().engine_speed, last);
  EXPECT_LT(got.size(), static_cast<std::size_t>(last - first + 1)) << "coalesced, not one per change";
  for (std::size_t i = 1; i < got.size(); ++i) {
    EXPECT_GT(got[i].engine_speed, got[i - 1].engine_speed) << "in order, never a backlog";
    // The pacing runs on the steady clock, a document's time is the system clock read just
    // after: a preemption between the two reads of one document (a loaded machine) moves
    // its stamp by a few ms, never the pacing.
    EXPECT_GE(got[i].time - got[i - 1].time, 95ms) << subscription.lines();
  }
}

}  // namespace
}  // namespace unima::test
