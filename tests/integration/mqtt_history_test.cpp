// History through a broker outage (SPEC §15, `mqtt.buffer`) against a real mosquitto, stopped
// and started to make the outage: the documents made meanwhile come after the reconnect on
// <prefix>/history/<bank>, oldest first with their own times, after the live documents and
// never in their place; kill -9 of the daemon mid-outage loses at most the last second;
// a tiny buffer drops its oldest and counts them; a corrupt buffer is set aside; a history
// longer than the sender reads ahead comes whole and in order.
//
// The subscriber that reads the history has a persistent session (mosquitto_sub -c, QoS 1)
// on a broker that keeps its sessions over a restart: what the bridge publishes the moment
// it reconnects is queued for it, however soon that is after the broker came back.

#include <csignal>
#include <set>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "mqtt/history_journal.hpp"
#include "tests/integration/bridge_fixture.hpp"
#include "tests/support/peers/mqtt_broker.hpp"
#include "tests/support/peers/mqtt_subscription.hpp"
#include "tests/support/shell_command.hpp"

namespace unima::test {
namespace {

using namespace std::chrono_literals;
using test_support::Broker;
using test_support::payloads;

constexpr auto history_topic = "fleet/site-17/history/D1";
constexpr auto live_topic = "fleet/site-17/D1";

/// The history's reader: a persistent session on the history and the live D1.
class DurableReader : public test_support::DurableSubscription {
 public:
  DurableReader(const Broker& broker, const std::filesystem::path& file)
      : DurableSubscription(broker, file, "history-reader", {history_topic, live_topic}) {}
};

class MqttHistory : public BridgeTest {
 protected:
  void SetUp() override {
    BridgeTest::SetUp();
    broker = std::make_unique<Broker>(dir.path());
    // Sessions and their queued messages kept over a restart; room for a long history.
    auto conf = test_support::read_file(dir.path() / "mosquitto.conf");
    conf.replace(conf.find("persistence false"), std::string("persistence false").size(),
                 "persistence true\npersistence_location " + dir.path().string() + "/\nmax_queued_messages 100000");
    test_support::write_file(dir.path() / "mosquitto.conf", conf);
    ASSERT_TRUE(broker->start());
    config.extra += test_support::site_17_mqtt(*broker);
  }
  void wait_online() {
    ASSERT_TRUE(eventually([&] { return broker->subscribe("fleet/site-17/status", 1, 1) == "fleet/site-17/status online\n"; }))
        << daemon->log();
  }
  void set_speed(Socket& feed, int speed) {
    feed.send(R"({"addr":5,"slot":0,"offset":1,"values":[)" + std::to_string(speed) + "]}\n");
  }
  nlohmann::json status() const {
    const auto r = test_support::run(std::string(UNIMA_BRIDGE_CLI) + " status --json --socket " + config.status_socket);
    return r.status == 0 ? nlohmann::json::parse(r.output) : nlohmann::json();
  }
  std::filesystem::path buffer_file() const { return dir.path() / "bridge.mqtt-buffer"; }
  void fill_small_buffer(const std::string& max_size, std::uintmax_t max_bytes, int values,
                         std::chrono::milliseconds pace = 120ms);
  std::unique_ptr<Broker> broker;
};

/// A document's engine_speed; 0 for null (D1 off-line, as after a restart before the feed).
int speed_of(const nlohmann::json& document) {
  return document["engine_speed"].is_number() ? document["engine_speed"].get<int>() : 0;
}

std::vector<nlohmann::json> documents(const std::string& lines, const std::string& topic) {
  std::vector<nlohmann::json> found;
  for (const auto& payload : payloads(lines, topic)) found.push_back(nlohmann::json::parse(payload));
  return found;
}

// Each document of the history is one the bridge made during the outage, in the order it
// made them, each with its own time; all of them after the live one on reconnect, which
// stays the retained document.
TEST_F(MqttHistory, AnOutageGivesOrderedHistoryWithOriginalTimesAfterTheLiveDocument) {
  start();
  wait_online();
  auto feed = feed_client();
  DurableReader reader(*broker, dir.path() / "reader");
  broker->stop();
  ASSERT_TRUE(daemon->wait_for_log("mqtt: the connection to"));
  // 20 s of outage, a new value every 150 ms: each its own document (at most one per 100 ms).
  constexpr int values = 133;
  for (int speed = 1; speed <= values; ++speed) {
    set_speed(feed, speed);
    std::this_thread::sleep_for(150ms);
  }
  const auto outage = status();
  ASSERT_TRUE(outage.is_object());
  EXPECT_FALSE(outage["mqtt"]["connected"].get<bool>());
  EXPECT_GE(outage["mqtt"]["buffer"]["messages"].get<int>() + 10, values) << outage.dump();
  ASSERT_TRUE(broker->start());
  // The client's back-off after 20 s may take as long again; the feed repeats the last value
  // meanwhile (no change, no document) so that D1 stays on-line.
  ASSERT_TRUE(eventually([&] {
    set_speed(feed, values);
    const auto history = documents(reader.lines(), history_topic);
    return !history.empty() && history.back()["engine_speed"] == values;
  }, 60000ms)) << reader.lines() << daemon->log();

  const auto lines = reader.lines();
  const auto history = documents(lines, history_topic);
  // Oldest first, every value, each time no earlier than the one before.
  int expected = 1;
  std::string previous_time;
  for (const auto& document : history) {
    const auto speed = speed_of(document);
    if (speed == expected) ++expected;
    EXPECT_LE(speed, expected) << "out of order: " << lines;
    const auto time = document["time"].get<std::string>();
    EXPECT_LE(previous_time, time) << lines;
    previous_time = time;
  }
  EXPECT_EQ(expected, values + 1) << "a value is missing: " << lines;
  // The live document of the reconnection came before the first history entry.
  std::optional<std::size_t> first_history, live_again;
  std::istringstream in(lines);
  std::size_t index = 0;
  for (std::string line; std::getline(in, line); ++index) {
    if (!first_history && line.starts_with(std::string(history_topic) + " ")) first_history = index;
    if (!live_again && line.starts_with(std::string(live_topic) + " ") &&
        nlohmann::json::parse(line.substr(std::string(live_topic).size() + 1))["engine_speed"] == values)
      live_again = index;
  }
  ASSERT_TRUE(first_history && live_again) << lines;
  EXPECT_LT(*live_again, *first_history) << lines;
  // Retained: the present, measured no earlier than any history (SPEC §21: the time of the
  // telegram that brought its value, which the last history entry shares).
  const auto retained = broker->subscribe(live_topic, 1);
  ASSERT_FALSE(retained.empty());
  const auto present = nlohmann::json::parse(retained.substr(std::string(live_topic).size() + 1));
  EXPECT_EQ(present["engine_speed"], values);
  EXPECT_LE(previous_time, present["time"].get<std::string>());
  // Delivered: counted, and the buffer empty again.
  EXPECT_TRUE(eventually([&] {
    const auto s = status();
    return s.is_object() && s["mqtt"]["buffer"]["messages"] == 0 && s["mqtt"]["buffer"]["history_sent"].get<std::size_t>() >= history.size();
  })) << status().dump();
}

// The history holds what the live stream would have carried under `report` (SPEC §21):
// with a deadband of 5 rpm, the moves within it made no document during the outage either.
TEST_F(MqttHistory, TheHistoryHoldsOnlyWhatTheDeadbandWouldHavePublished) {
  config.extra += "report: { deadband: { D1.engine_speed: 5 } }\n";
  start();
  wait_online();
  auto feed = feed_client();
  set_speed(feed, 1000);
  ASSERT_TRUE(eventually([&] { return broker->subscribe(live_topic, 1).find("\"engine_speed\":1000") != std::string::npos; }))
      << daemon->log();
  DurableReader reader(*broker, dir.path() / "reader");
  broker->stop();
  ASSERT_TRUE(daemon->wait_for_log("mqtt: the connection to"));
  for (const int speed : {1002, 1010, 1013, 1020, 1016}) {
    set_speed(feed, speed);
    std::this_thread::sleep_for(150ms);
  }
  ASSERT_TRUE(broker->start());
  std::vector<int> speeds;
  ASSERT_TRUE(eventually([&] {
    set_speed(feed, 1016);  // no change: D1 stays on-line, and nothing more is made
    speeds.clear();
    for (const auto& document : documents(reader.lines(), history_topic)) speeds.push_back(speed_of(document));
    return !speeds.empty() && speeds.back() == 1020;
  }, 60000ms)) << reader.lines() << daemon->log();
  EXPECT_EQ(speeds, (std::vector<int>{1010, 1020})) << "1002, 1013 and 1016 are within 5 of the value published before them\n"
                                                   << reader.lines();
}

// kill -9 in the outage: what was made up to a second before the kill comes after the
// restart and the reconnect.
TEST_F(MqttHistory, AKillDuringTheOutageLosesAtMostTheLastSecond) {
  start();
  wait_online();
  auto feed = feed_client();
  DurableReader reader(*broker, dir.path() / "reader");
  broker->stop();
  ASSERT_TRUE(daemon->wait_for_log("mqtt: the connection to"));
  std::vector<std::pair<int, std::chrono::steady_clock::time_point>> sent;
  for (int speed = 1; speed <= 25; ++speed) {
    set_speed(feed, speed);
    sent.emplace_back(speed, std::chrono::steady_clock::now());
    std::this_thread::sleep_for(120ms);
  }
  const auto killed_at = std::chrono::steady_clock::now();
  daemon->signal(SIGKILL);
  ASSERT_TRUE(eventually([&] { return !daemon->running(); }));
  const auto kept = test_support::read_file(buffer_file());
  daemon.reset();
  start();
  ASSERT_TRUE(daemon->wait_for_log("history buffer")) << daemon->log();
  ASSERT_TRUE(broker->start());
  int last_kept = 0;
  for (const auto& [speed, at] : sent)
    if (at + 1000ms < killed_at) last_kept = speed;
  ASSERT_GT(last_kept, 10);
  ASSERT_TRUE(eventually([&] {
    for (const auto& document : documents(reader.lines(), history_topic))
      if (document["engine_speed"] == last_kept) return true;
    return false;
  }, 15000ms)) << "value " << last_kept << " of more than a second before the kill is missing:\n"
               << reader.lines() << "\nthe buffer held:\n" << kept << daemon->log();
  std::set<int> speeds;
  for (const auto& document : documents(reader.lines(), history_topic)) speeds.insert(speed_of(document));
  for (int speed = 1; speed <= last_kept; ++speed) EXPECT_TRUE(speeds.contains(speed)) << speed << reader.lines();
}

// A small max_size: the newest history is kept, the oldest dropped and counted.
void MqttHistory::fill_small_buffer(const std::string& max_size, std::uintmax_t max_bytes, int values,
                                    std::chrono::milliseconds pace) {
  config.extra = "mqtt: { broker: 'mqtt://127.0.0.1:" + std::to_string(broker->port()) +
                 "', client_id: site-17, topic: fleet/site-17, publish: { period: 60s }, buffer: { max_size: " + max_size +
                 " } }\n";
  start();
  wait_online();
  auto feed = feed_client();
  DurableReader reader(*broker, dir.path() / "reader");
  broker->stop();
  ASSERT_TRUE(daemon->wait_for_log("mqtt: the connection to"));
  for (int speed = 1; speed <= values; ++speed) {
    set_speed(feed, speed);
    std::this_thread::sleep_for(pace);
  }
  ASSERT_TRUE(eventually([&] {
    const auto s = status();
    return s.is_object() && s["mqtt"]["buffer"]["dropped"].get<int>() > 0;
  })) << status().dump() << daemon->log();
  EXPECT_TRUE(daemon->wait_for_log("is full")) << daemon->log();
  EXPECT_LE(std::filesystem::file_size(buffer_file()), max_bytes);
  ASSERT_TRUE(broker->start());
  // The client's back-off after 20 s may take as long again; the feed repeats the last value
  // meanwhile (no change, no document) so that D1 stays on-line.
  ASSERT_TRUE(eventually([&] {
    set_speed(feed, values);
    const auto history = documents(reader.lines(), history_topic);
    return !history.empty() && history.back()["engine_speed"] == values;
  }, 60000ms)) << "the newest must be kept: " << reader.lines() << daemon->log();
  const auto history = documents(reader.lines(), history_topic);
  EXPECT_GT(speed_of(history.front()), 1) << "the oldest are the ones dropped";
  int previous = 0;
  for (const auto& document : history) {
    EXPECT_GE(speed_of(document), previous);
    previous = speed_of(document);
  }
  const auto dropped = status()["mqtt"]["buffer"]["dropped"].get<int>();
  EXPECT_GE(static_cast<int>(history.size()) + dropped, values) << "each document made is sent or counted dropped";
  // /metrics says the same (its text from the status, metrics_test).
  const auto text = test_support::run(std::string(UNIMA_BRIDGE_CLI) + " status --socket " + config.status_socket).output;
  EXPECT_NE(text.find("dropped when full"), std::string::npos) << text;
}

// 64 KiB: some eight D1 documents of this config.
TEST_F(MqttHistory, AFullBufferDropsTheOldestAndCountsThem) { fill_small_buffer("64KiB", 65536, 40); }

// Issue 43, finding 11: 8 KiB holds one D1 document and not the eighth left free beside it;
// every entry was dropped and nothing sent after the reconnect. The newest stays.
TEST_F(MqttHistory, ABufferThatHoldsOneDocumentKeepsTheNewest) { fill_small_buffer("8KiB", 8192, 12); }

// A history longer than the sender holds read ahead (400 entries), as a restart after a
// long outage finds it, comes whole on one connection: every entry once, oldest first.
TEST_F(MqttHistory, AHistoryLongerThanTheReadAheadComesWholeAndInOrder) {
  constexpr int entries = 1000;
  std::string journal(mqtt::history_header);
  for (int i = 1; i <= entries; ++i)
    journal += mqtt::encode_history_entry({static_cast<std::uint64_t>(i), "D1", R"({"engine_speed":)" + std::to_string(i) + "}"});
  test_support::write_file(buffer_file(), journal);
  DurableReader reader(*broker, dir.path() / "reader");
  start();
  ASSERT_TRUE(eventually([&] {
    const auto s = status();
    return s.is_object() && s["mqtt"]["buffer"]["messages"] == 0 && s["mqtt"]["buffer"]["history_sent"] == entries;
  }, 15000ms)) << status().dump() << daemon->log();
  ASSERT_TRUE(eventually([&] { return documents(reader.lines(), history_topic).size() >= entries; }))
      << documents(reader.lines(), history_topic).size();
  const auto history = documents(reader.lines(), history_topic);
  ASSERT_EQ(history.size(), static_cast<std::size_t>(entries));
  for (int i = 0; i < entries; ++i) ASSERT_EQ(history[static_cast<std::size_t>(i)]["engine_speed"], i + 1) << "at " << i;
}

TEST_F(MqttHistory, ACorruptBufferIsSetAsideAndANewOneBegun) {
  test_support::write_file(buffer_file(), "unima-bridge mqtt history 1\nE 1 D1 {} 00000000\nE 2 D1 {} 00000000\n");
  start();
  ASSERT_TRUE(daemon->wait_for_log("kept aside as")) << daemon->log();
  std::size_t aside = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
    if (entry.path().filename().string().starts_with("bridge.mqtt-buffer.corrupt-")) {
      ++aside;
      EXPECT_EQ(test_support::read_file(entry.path()).substr(0, 28), "unima-bridge mqtt history 1\n");
    }
  EXPECT_EQ(aside, 1u);
  wait_online();  // the new buffer is begun before the daemon runs
  EXPECT_EQ(test_support::read_file(buffer_file()), "unima-bridge mqtt history 1\n");
}

}  // namespace
}  // namespace unima::test
