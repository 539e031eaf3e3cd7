// sparkplug/edge_session (SPEC §16): the edge node's decisions — bdSeq per CONNECT, seq
// across births, data and deaths, births per device, DDEATH/DBIRTH with presence, the
// primary host's STATE, rebirth, and what an NCMD or DCMD means.

#include <gtest/gtest.h>

#include <algorithm>
#include <deque>
#include <map>

#include "config/config.hpp"
#include "sparkplug/edge_session.hpp"
#include "sparkplug/metric_value.hpp"
#include "sparkplug/payload_codec.hpp"
#include "values/store_snapshot.hpp"

namespace unima::sparkplug {
namespace {

using banks::BankId;

constexpr std::uint64_t now_ms = 1700000000000;

Payload decoded(const Message& message) {
  auto result = decode_payload(message.payload);
  if (!result.payload) throw std::runtime_error("undecodable " + message.topic);
  return *result.payload;
}

const Metric* find(const Payload& payload, std::string_view name) {
  for (const auto& m : payload.metrics)
    if (m.name == name) return &m;
  return nullptr;
}

std::string encoded(const Payload& payload) {
  const auto bytes = encode_payload(payload);
  return std::string(bytes.begin(), bytes.end());
}

std::string command_of(std::string name, DataType type, MetricValue value) {
  Metric metric;
  metric.name = std::move(name);
  metric.datatype = type;
  metric.value = std::move(value);
  Payload payload;
  payload.metrics.push_back(std::move(metric));
  return encoded(payload);
}

class SparkplugEdgeSession : public ::testing::Test {
 protected:
  SparkplugEdgeSession()
      : config(config::load_text("devices:\n  D1: { type: unigen-chp, address: 5 }\n", "edge.yaml")),
        model(config),
        store(config::bank_shapes(config)) {
    store.set_mapping(config.mapping);
    store.set_online(BankId::D1, true);
    for (unsigned n = 1; n <= 7; ++n) store.set_online(banks::module_bank(n), true);
  }

  /// The devices as the service hands them to a step, from the store; their values stay
  /// with the fixture. Each device read is counted in `reads`.
  Devices devices() {
    changes.clear();
    for (const auto& layout : model.banks()) changes.push_back(store.changes(layout.bank));
    return {changes, [this](std::size_t i) {
              const auto& layout = model.banks()[i];
              const auto snapshot = values::snapshot_of(store);
              const auto& values = evaluated.emplace_back(model.evaluate(layout.bank, snapshot));
              reads.push_back(layout.bank);
              const auto deadband = deadbands.find(layout.bank);
              const auto measured = measured_ms.find(layout.bank);
              return DeviceReading{&layout, values, snapshot[banks::index_of(layout.bank)].online,
                                   deadband == deadbands.end() ? std::span<const double>() : std::span<const double>(deadband->second),
                                   measured == measured_ms.end() ? std::nullopt : std::optional<std::uint64_t>(measured->second)};
            }};
  }
  std::vector<std::uint64_t> changes;
  std::deque<std::vector<values::Value>> evaluated;
  std::vector<BankId> reads;
  std::map<BankId, std::vector<double>> deadbands;    // none for a bank: every change counts
  std::map<BankId, std::uint64_t> measured_ms;        // none for a bank: the step's now

  /// Steps of these tests: every change at once, no full re-send within a test's span,
  /// unless a test says otherwise.
  static constexpr report::Intervals every_change{.min_interval = std::chrono::milliseconds(0),
                                                  .max_interval = std::chrono::hours(1), .on_change = true};

  EdgeSession connected_session(bool primary_host = false, std::optional<std::uint64_t> last = std::nullopt,
                                report::Intervals intervals = every_change) {
    EdgeSession session({"plant-7", "bridge-17", primary_host, intervals}, last);
    session.begin_connect();
    session.connected();
    return session;
  }

  /// The steady time point of a step at `at_ms` (one clock for the tests: the payloads' ms).
  static EdgeSession::Clock::time_point steady(std::uint64_t at_ms) {
    return EdgeSession::Clock::time_point(std::chrono::milliseconds(at_ms));
  }
  /// `session`'s step at `at_ms`, of the devices as the store has them.
  std::vector<Message> step(EdgeSession& session, std::uint64_t at_ms = now_ms) {
    return session.step(devices(), steady(at_ms), at_ms);
  }
  /// The messages of `messages` on device `bank`'s topics.
  static std::vector<Message> of_bank(const std::vector<Message>& messages, BankId bank) {
    std::vector<Message> found;
    for (const auto& m : messages)
      if (m.topic.ends_with("/" + std::string(banks::bank_name(bank)))) found.push_back(m);
    return found;
  }

  config::Config config;
  values::ValueModel model;
  banks::RegisterStore store;
};

TEST_F(SparkplugEdgeSession, BdSeqCountsConnectsModulo256AndTheDeathCarriesItAsInt64) {
  EdgeSession first({"g", "n", false, every_change}, std::nullopt);
  EXPECT_EQ(first.begin_connect(), 0u);
  EXPECT_EQ(first.begin_connect(), 1u);
  EdgeSession kept({"g", "n", false, every_change}, 254);
  EXPECT_EQ(kept.begin_connect(), 255u);
  EXPECT_EQ(kept.begin_connect(), 0u);
  const auto death = kept.death(now_ms);
  EXPECT_EQ(death.topic, "spBv1.0/g/NDEATH/n");
  const auto payload = decoded(death);
  EXPECT_FALSE(payload.seq);
  const auto* bd_seq = find(payload, "bdSeq");
  ASSERT_NE(bd_seq, nullptr);
  EXPECT_EQ(bd_seq->datatype, DataType::Int64);
  EXPECT_EQ(std::get<std::uint64_t>(bd_seq->value), 0u);
}

TEST_F(SparkplugEdgeSession, BirthsOnConnectNodeFirstThenEveryDeviceWithSeqFromZero) {
  EdgeSession idle({"plant-7", "bridge-17", false, every_change}, 4);
  EXPECT_TRUE(step(idle).empty());  // not connected: nothing

  auto session = connected_session(false, 4);
  const auto births = step(session);
  ASSERT_EQ(births.size(), 1 + model.banks().size());
  EXPECT_EQ(births[0].topic, "spBv1.0/plant-7/NBIRTH/bridge-17");
  const auto nbirth = decoded(births[0]);
  EXPECT_EQ(nbirth.seq, 0u);
  ASSERT_NE(find(nbirth, "bdSeq"), nullptr);
  EXPECT_EQ(std::get<std::uint64_t>(find(nbirth, "bdSeq")->value), 5u);
  const auto* rebirth = find(nbirth, "Node Control/Rebirth");
  ASSERT_NE(rebirth, nullptr);
  EXPECT_EQ(rebirth->datatype, DataType::Boolean);
  EXPECT_EQ(std::get<bool>(rebirth->value), false);
  for (std::size_t i = 1; i < births.size(); ++i) {
    EXPECT_EQ(births[i].topic, "spBv1.0/plant-7/DBIRTH/bridge-17/" + std::string(banks::bank_name(model.banks()[i - 1].bank)));
    EXPECT_EQ(decoded(births[i]).seq, i);
  }
  EXPECT_TRUE(step(session).empty());  // nothing changed
  EXPECT_EQ(session.counters().births, births.size());
}

TEST_F(SparkplugEdgeSession, DataOnChangeOnlyAndSeqWrapsAfter255) {
  auto session = connected_session();
  const auto births = step(session);
  std::uint64_t expected = births.size();  // the next seq
  for (int i = 0; i < 300; ++i) {
    store.write(BankId::W, 0, static_cast<std::uint16_t>(1000 + i));
    const auto data = step(session);
    ASSERT_EQ(data.size(), 1u);
    EXPECT_EQ(data[0].topic, "spBv1.0/plant-7/DDATA/bridge-17/W");
    const auto payload = decoded(data[0]);
    EXPECT_EQ(payload.seq, expected % 256);
    ++expected;
    ASSERT_EQ(payload.metrics.size(), 1u);
    EXPECT_EQ(payload.metrics[0].name, "w_00");
  }
  EXPECT_EQ(session.counters().data, 300u);
}

// SPEC §21: a DDATA carries the values that moved beyond their deadbands, each compared
// with what the host was last sent of it, and every metric is timed when its values were
// measured, not when the message goes.
TEST_F(SparkplugEdgeSession, DataHoldsMovesBeyondTheDeadbandTimedWhenMeasured) {
  const auto& layout = *model.bank(BankId::D1);
  auto& d1_deadbands = deadbands[BankId::D1];
  d1_deadbands.assign(layout.values.size(), 0);
  for (std::size_t i = 0; i < layout.values.size(); ++i)
    if (layout.values[i].name == "engine_speed") d1_deadbands[i] = 5;
  const auto step_measured = [&](EdgeSession& session, std::uint64_t measured) {
    measured_ms[BankId::D1] = measured;
    return of_bank(step(session), BankId::D1);
  };
  auto session = connected_session();
  const std::vector<std::uint16_t> speed_1500 = {1500};
  store.store_telegram(BankId::D1, 1, speed_1500);
  const auto births = step_measured(session, now_ms - 7000);
  ASSERT_EQ(births.size(), 1u);
  const auto birth = decoded(births.back());
  ASSERT_NE(find(birth, "engine_speed"), nullptr);
  EXPECT_EQ(find(birth, "engine_speed")->timestamp, now_ms - 7000) << "a birth's metrics carry the measurement's time";

  const std::vector<std::uint16_t> speed_1504 = {1504};
  store.store_telegram(BankId::D1, 1, speed_1504);
  EXPECT_TRUE(step_measured(session, now_ms - 5000).empty()) << "4 is within the deadband of 5";
  const std::vector<std::uint16_t> speed_1506 = {1506};
  store.store_telegram(BankId::D1, 1, speed_1506);
  const auto data = step_measured(session, now_ms - 3000);
  ASSERT_EQ(data.size(), 1u) << "6 from the 1500 the host has";
  const auto payload = decoded(data[0]);
  ASSERT_EQ(payload.metrics.size(), 1u);
  EXPECT_EQ(payload.metrics[0].name, "engine_speed");
  EXPECT_EQ(std::get<std::uint32_t>(payload.metrics[0].value), 1506u);
  EXPECT_EQ(payload.metrics[0].timestamp, now_ms - 3000);
  EXPECT_EQ(payload.timestamp, now_ms) << "the message's own time is when it goes";

  const std::vector<std::uint16_t> oil = {853};
  store.store_telegram(BankId::D1, 0x21, oil);
  const auto oil_data = step_measured(session, now_ms - 1000);
  ASSERT_EQ(oil_data.size(), 1u) << "no deadband: every change";
  EXPECT_EQ(decoded(oil_data[0]).metrics.size(), 1u) << "the speed did not move again";

  // A move within the deadband sends nothing by itself, and rides along with the next
  // DDATA of its device: the host then has what the next comparison is against.
  const std::vector<std::uint16_t> speed_1509 = {1509};
  store.store_telegram(BankId::D1, 1, speed_1509);
  EXPECT_TRUE(step_measured(session, now_ms - 900).empty()) << "3 from 1506";
  const std::vector<std::uint16_t> oil_again = {860};
  store.store_telegram(BankId::D1, 0x21, oil_again);
  const auto both = step_measured(session, now_ms - 800);
  ASSERT_EQ(both.size(), 1u);
  const auto both_payload = decoded(both[0]);
  ASSERT_EQ(both_payload.metrics.size(), 2u);
  ASSERT_NE(find(both_payload, "engine_speed"), nullptr);
  EXPECT_EQ(std::get<std::uint32_t>(find(both_payload, "engine_speed")->value), 1509u) << "rides along";
  const std::vector<std::uint16_t> speed_1513 = {1513};
  store.store_telegram(BankId::D1, 1, speed_1513);
  EXPECT_TRUE(step_measured(session, now_ms - 700).empty()) << "4 from the 1509 the host has now";
}

// SPEC §21, report.min_interval: a device's DDATA goes on the leading edge — at once when
// its last message is min_interval old, else when it is, once, with the values of then
// (never a backlog) — each device on its own; a held-back device is not even read.
TEST_F(SparkplugEdgeSession, MinIntervalPacesEachDevicesDdataOnTheLeadingEdge) {
  auto session = connected_session(false, std::nullopt, {.min_interval = std::chrono::milliseconds(250),
                                                         .max_interval = std::chrono::hours(1), .on_change = true});
  ASSERT_FALSE(step(session, now_ms).empty());
  EXPECT_EQ(session.next_due(), steady(now_ms) + std::chrono::hours(1));

  store.write(BankId::W, 0, 10);
  EXPECT_TRUE(step(session, now_ms + 100).empty()) << "100 ms after W's birth";
  EXPECT_EQ(session.next_due(), steady(now_ms + 250));
  store.write(BankId::W, 0, 11);
  reads.clear();
  EXPECT_TRUE(step(session, now_ms + 200).empty());
  EXPECT_TRUE(reads.empty()) << "a held-back device is not read";
  EXPECT_TRUE(step(session, now_ms + 249).empty());
  const auto held = step(session, now_ms + 250);
  ASSERT_EQ(held.size(), 1u) << "once for both changes";
  EXPECT_EQ(held[0].topic, "spBv1.0/plant-7/DDATA/bridge-17/W");
  const auto held_payload = decoded(held[0]);
  ASSERT_EQ(held_payload.metrics.size(), 1u);
  EXPECT_FLOAT_EQ(std::get<float>(held_payload.metrics[0].value), 1.1f) << "the value of then, W in tenths";

  store.write(BankId::X, 0, 1);
  const auto x = step(session, now_ms + 260);
  ASSERT_EQ(x.size(), 1u) << "X's last message is its birth, 260 ms ago: at once";
  EXPECT_EQ(x[0].topic, "spBv1.0/plant-7/DDATA/bridge-17/X");

  store.write(BankId::W, 0, 12);
  EXPECT_TRUE(step(session, now_ms + 400).empty()) << "150 ms after W's last DDATA";
  EXPECT_EQ(session.next_due(), steady(now_ms + 500));
  ASSERT_EQ(step(session, now_ms + 500).size(), 1u);
  store.write(BankId::W, 0, 13);
  EXPECT_EQ(step(session, now_ms + 900).size(), 1u) << "after a quiet while: at once";
  EXPECT_EQ(session.counters().data, 4u);
}

// SPEC §21, report.max_interval: every device on-line gets a DDATA of all its metrics at
// least every max_interval after its last message, each metric with the time its values
// were measured — a re-send keeps its old time; a dead device gets none.
TEST_F(SparkplugEdgeSession, MaxIntervalResendsEveryMetricWithItsMeasurementTime) {
  auto session = connected_session(false, std::nullopt, {.min_interval = std::chrono::milliseconds(100),
                                                         .max_interval = std::chrono::seconds(10), .on_change = true});
  const std::vector<std::uint16_t> speed = {1500};
  store.store_telegram(BankId::D1, 1, speed);
  store.set_online(banks::module_bank(3), false);
  measured_ms[BankId::D1] = now_ms - 60'000;
  const auto births = step(session, now_ms);
  const auto d1_birth = decoded(of_bank(births, BankId::D1).at(0));
  EXPECT_EQ(session.next_due(), steady(now_ms + 10'000));
  EXPECT_TRUE(step(session, now_ms + 2'999).empty());
  store.write(BankId::W, 0, 10);
  ASSERT_EQ(step(session, now_ms + 3'000).size(), 1u);  // W's max_interval now counts from here
  EXPECT_TRUE(step(session, now_ms + 9'999).empty());

  const auto resent = step(session, now_ms + 10'000);
  EXPECT_TRUE(of_bank(resent, BankId::W).empty()) << "W's last DDATA is 7 s old";
  EXPECT_TRUE(of_bank(resent, banks::module_bank(3)).empty()) << "S3 is dead: no data";
  const auto d1 = of_bank(resent, BankId::D1);
  ASSERT_EQ(d1.size(), 1u);
  EXPECT_EQ(d1[0].topic, "spBv1.0/plant-7/DDATA/bridge-17/D1");
  const auto payload = decoded(d1[0]);
  EXPECT_EQ(payload.timestamp, now_ms + 10'000) << "the message's own time is when it goes";
  ASSERT_EQ(payload.metrics.size(), d1_birth.metrics.size()) << "every metric, changed or not";
  for (const auto& metric : payload.metrics) EXPECT_EQ(metric.timestamp, now_ms - 60'000) << *metric.name;
  ASSERT_NE(find(payload, "engine_speed"), nullptr);
  EXPECT_EQ(std::get<std::uint32_t>(find(payload, "engine_speed")->value), 1500u);
  EXPECT_FALSE(of_bank(resent, BankId::X).empty()) << "every device born and on-line";

  EXPECT_EQ(session.next_due(), steady(now_ms + 13'000)) << "W's, 10 s after its last";
  const auto w = step(session, now_ms + 13'000);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(decoded(w[0]).metrics.size(), decoded(of_bank(births, BankId::W).at(0)).metrics.size());
}

// A change to or from null always counts, whatever the deadband.
TEST_F(SparkplugEdgeSession, AChangeToOrFromNullAlwaysCounts) {
  const auto& layout = *model.bank(BankId::D1);
  deadbands[BankId::D1].assign(layout.values.size(), 1000);
  auto session = connected_session();
  const std::vector<std::uint16_t> speed_1500 = {1500};
  store.store_telegram(BankId::D1, 1, speed_1500);
  step(session);
  const std::vector<std::uint16_t> not_measured = {0x7FFF};
  store.store_telegram(BankId::D1, 1, not_measured);
  const auto to_null = of_bank(step(session), BankId::D1);
  ASSERT_EQ(to_null.size(), 1u) << "to null";
  const auto to_null_payload = decoded(to_null[0]);  // find() points into it
  const auto* speed = find(to_null_payload, "engine_speed");
  ASSERT_NE(speed, nullptr);
  EXPECT_EQ(speed->is_null, true);
  const std::vector<std::uint16_t> speed_1501 = {1501};
  store.store_telegram(BankId::D1, 1, speed_1501);
  const auto from_null = of_bank(step(session), BankId::D1);
  ASSERT_EQ(from_null.size(), 1u) << "from null";
  EXPECT_EQ(std::get<std::uint32_t>(find(decoded(from_null[0]), "engine_speed")->value), 1501u);
  const std::vector<std::uint16_t> speed_1502 = {1502};
  store.store_telegram(BankId::D1, 1, speed_1502);
  EXPECT_TRUE(of_bank(step(session), BankId::D1).empty()) << "1 within 1000";
}

// A value a refused command left as it was goes to the host again in its device's next
// DDATA, changed or not — no sooner than min_interval after the device's last message.
TEST_F(SparkplugEdgeSession, AResendGoesInTheNextDdataItsMinIntervalAllows) {
  auto session = connected_session(false, std::nullopt, {.min_interval = std::chrono::milliseconds(250),
                                                         .max_interval = std::chrono::hours(1), .on_change = true});
  step(session, now_ms);
  session.resend(BankId::W, 3);
  EXPECT_TRUE(step(session, now_ms + 100).empty());
  EXPECT_EQ(session.next_due(), steady(now_ms + 250));
  const auto again = step(session, now_ms + 250);
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0].topic, "spBv1.0/plant-7/DDATA/bridge-17/W");
  const auto payload = decoded(again[0]);
  ASSERT_EQ(payload.metrics.size(), 1u);
  EXPECT_EQ(payload.metrics[0].name, "w_03");
  EXPECT_TRUE(step(session, now_ms + 600).empty()) << "once";
}

// A reload that keeps the connection: every birth again, the new intervals from them on.
TEST_F(SparkplugEdgeSession, AReloadBirthsAgainAndTakesTheNewIntervals) {
  auto session = connected_session();
  step(session, now_ms);
  session.reload({.min_interval = std::chrono::seconds(1), .max_interval = std::chrono::hours(1), .on_change = true});
  const auto births = step(session, now_ms + 10);
  ASSERT_FALSE(births.empty());
  EXPECT_EQ(births[0].topic, "spBv1.0/plant-7/NBIRTH/bridge-17");
  store.write(BankId::W, 0, 10);
  EXPECT_TRUE(step(session, now_ms + 500).empty()) << "within the new min_interval of the births";
  EXPECT_EQ(step(session, now_ms + 1'010).size(), 1u);
}

TEST_F(SparkplugEdgeSession, AnOfflineDeviceDiesAndIsBornAgainWhenBack) {
  store.set_online(BankId::D1, false);
  auto session = connected_session();
  const auto births = step(session);
  // D1's birth names its metrics, then its death says it is gone.
  std::size_t d1 = 0;
  for (std::size_t i = 0; i < births.size(); ++i)
    if (births[i].topic.ends_with("DBIRTH/bridge-17/D1")) d1 = i;
  ASSERT_GT(d1, 0u);
  ASSERT_LT(d1 + 1, births.size());
  EXPECT_EQ(births[d1 + 1].topic, "spBv1.0/plant-7/DDEATH/bridge-17/D1");

  // C's on-line bits change with D1: its DDATA comes too.
  const auto of_d1 = [](const std::vector<Message>& messages) {
    std::vector<Message> d1;
    for (const auto& m : messages)
      if (m.topic.ends_with("/D1")) d1.push_back(m);
    return d1;
  };
  store.set_online(BankId::D1, true);
  auto back = of_d1(step(session));
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].topic, "spBv1.0/plant-7/DBIRTH/bridge-17/D1");
  store.set_online(BankId::D1, false);
  auto gone = of_d1(step(session));
  ASSERT_EQ(gone.size(), 1u);
  EXPECT_EQ(gone[0].topic, "spBv1.0/plant-7/DDEATH/bridge-17/D1");
  EXPECT_TRUE(decoded(gone[0]).metrics.empty());
  EXPECT_TRUE(step(session).empty());  // dead: no data
}

TEST_F(SparkplugEdgeSession, APrimaryHostHoldsBirthsUntilOnlineAndItsOfflineIsTheNodesDeath) {
  auto session = connected_session(true);
  EXPECT_TRUE(step(session).empty());
  EXPECT_EQ(session.host_state("not json", std::nullopt), HostVerdict::none);
  EXPECT_EQ(session.host_state(R"({"online":false,"timestamp":10})", std::nullopt), HostVerdict::none);
  EXPECT_TRUE(step(session).empty());
  EXPECT_EQ(session.host_state(R"({"online":true,"timestamp":20})", std::nullopt), HostVerdict::birth);
  EXPECT_FALSE(step(session).empty());
  EXPECT_EQ(session.host_state(R"({"online":false,"timestamp":15})", std::nullopt), HostVerdict::none);  // older: ignored
  EXPECT_EQ(session.host()  , EdgeSession::HostState::online);
  EXPECT_EQ(session.host_state(R"({"online":false,"timestamp":30})", std::nullopt), HostVerdict::death);
  session.disconnected();
  EXPECT_FALSE(session.born());
  // Connected again: the node waits for the host again, the next bdSeq.
  EXPECT_EQ(session.begin_connect(), 1u);
  session.connected();
  EXPECT_EQ(session.host_state(R"({"online":false,"timestamp":30})", std::nullopt), HostVerdict::none);
  EXPECT_TRUE(step(session).empty());
  EXPECT_EQ(session.host_state(R"({"online":true,"timestamp":40})", std::nullopt), HostVerdict::birth);
  const auto births = step(session);
  ASSERT_FALSE(births.empty());
  EXPECT_EQ(std::get<std::uint64_t>(find(decoded(births[0]), "bdSeq")->value), 1u);
}

// A forged STATE stamped far in the future (2^64 - 1) would make every real STATE look
// old and keep the node dead: one more than a minute ahead of a synchronised clock is
// ignored, and the newest stamp seen is forgotten at each connection (issue 43, finding 4).
TEST_F(SparkplugEdgeSession, AStateFromTheFutureIsIgnoredAndNoStampOutlivesItsConnection) {
  auto session = connected_session(true);
  const std::uint64_t clock = 1'764'000'000'000;
  EXPECT_EQ(session.host_state(R"({"online":true,"timestamp":18446744073709551615})", clock), HostVerdict::from_the_future);
  EXPECT_EQ(session.host(), EdgeSession::HostState::unknown);
  EXPECT_EQ(session.host_state(R"({"online":true,"timestamp":)" + std::to_string(clock + max_host_clock_lead_ms + 1) + "}", clock),
            HostVerdict::from_the_future);
  EXPECT_EQ(session.host_state(R"({"online":true,"timestamp":)" + std::to_string(clock + max_host_clock_lead_ms) + "}", clock),
            HostVerdict::birth);
  EXPECT_FALSE(step(session).empty());
  // A clock that never synchronised judges nothing: the forged stamp is taken, and holds
  // until the connection ends.
  EXPECT_EQ(session.host_state(R"({"online":false,"timestamp":18446744073709551615})", std::nullopt), HostVerdict::death);
  EXPECT_EQ(session.host_state(R"({"online":true,"timestamp":)" + std::to_string(clock) + "}", std::nullopt), HostVerdict::none);
  session.disconnected();
  session.begin_connect();
  session.connected();
  EXPECT_EQ(session.host_state(R"({"online":true,"timestamp":)" + std::to_string(clock) + "}", std::nullopt), HostVerdict::birth);
}

TEST_F(SparkplugEdgeSession, RebirthByNcmdRepeatsEveryBirthWithTheSameBdSeqAndSeqFromZero) {
  auto session = connected_session(false, 9);
  const auto first = step(session);
  const auto rebirth = session.command("", command_of("Node Control/Rebirth", DataType::Boolean, true), model, false);
  EXPECT_TRUE(rebirth.rebirth);
  EXPECT_TRUE(rebirth.malformed.empty());
  session.rebirth();
  const auto again = step(session);
  ASSERT_EQ(again.size(), first.size());
  EXPECT_EQ(decoded(again[0]).seq, 0u);
  EXPECT_EQ(std::get<std::uint64_t>(find(decoded(again[0]), "bdSeq")->value), 10u);
  EXPECT_EQ(session.counters().taken, 1u);

  EXPECT_FALSE(session.command("", command_of("Node Control/Rebirth", DataType::Boolean, false), model, false).rebirth);
  EXPECT_FALSE(session.command("", command_of("Node Control/Next Server", DataType::Boolean, true), model, false).rebirth);
  EXPECT_EQ(session.counters().refused, 2u);
  const auto wrong_type = session.command("", command_of("Node Control/Rebirth", DataType::String, std::string("yes")), model, false);
  EXPECT_FALSE(wrong_type.rebirth);
  EXPECT_EQ(wrong_type.malformed, "Node Control/Rebirth is not a Boolean");
  EXPECT_EQ(session.counters().malformed, 1u);
}

TEST_F(SparkplugEdgeSession, DcmdToWOrXIsAWriteInTheMetricsUnitOnlyWhenCommandsAreTaken) {
  auto session = connected_session();
  const auto w = session.command("W", command_of("w_03", DataType::Float, 12.3f), model, true);
  ASSERT_EQ(w.writes.size(), 1u);
  EXPECT_EQ(w.writes[0].bank, BankId::W);
  EXPECT_EQ(w.writes[0].offset, 3u);
  EXPECT_EQ(w.writes[0].raw, 123u);
  const auto negative = session.command("W", command_of("w_00", DataType::Double, -1.5), model, true);
  ASSERT_EQ(negative.writes.size(), 1u);
  EXPECT_EQ(negative.writes[0].raw, 0xFFF1u);  // −15 tenths
  const auto x = session.command("X", command_of("x", DataType::UInt16, integer_value(DataType::UInt16, 5)), model, true);
  ASSERT_EQ(x.writes.size(), 1u);
  EXPECT_EQ(x.writes[0].bank, BankId::X);
  EXPECT_EQ(x.writes[0].raw, 5u);
  EXPECT_EQ(session.counters().taken, 3u);

  EXPECT_TRUE(session.command("W", command_of("w_03", DataType::Float, 1.0f), model, false).writes.empty());
  EXPECT_TRUE(session.command("D1", command_of("engine_speed", DataType::UInt16, 1u), model, true).writes.empty());
  EXPECT_TRUE(session.command("W", command_of("w_99", DataType::Float, 1.0f), model, true).writes.empty());
  EXPECT_TRUE(session.command("W", command_of("w_01", DataType::Float, 99999.0f), model, true).writes.empty());
  EXPECT_EQ(session.counters().refused, 4u);

  EXPECT_EQ(session.command("W", command_of("w_03", DataType::String, std::string("1")), model, true).malformed,
            "w_03 is not a number");
  EXPECT_FALSE(session.command("W", std::string("\x0a\x05", 2), model, true).malformed.empty());  // truncated
  const auto huge = session.command("W", std::string(max_command_bytes + 1, '\0'), model, true);
  EXPECT_EQ(huge.malformed, "65537 bytes, more than the 65536 a command may have");
  EXPECT_EQ(session.counters().malformed, 3u);
  EXPECT_EQ(session.counters().taken, 3u);
}

// X's bits are Boolean metrics (SPEC §16): a DCMD to x.N writes bit N alone — the mask
// keeps the other bits, which the write path takes from the register as it is then.
TEST_F(SparkplugEdgeSession, DcmdToABitOfXWritesThatBitAlone) {
  auto session = connected_session();
  const auto set = session.command("X", command_of("x.3", DataType::Boolean, true), model, true);
  ASSERT_EQ(set.writes.size(), 1u) << (set.refused.empty() ? set.malformed : set.refused.front());
  EXPECT_EQ(set.writes[0].bank, BankId::X);
  EXPECT_EQ(set.writes[0].offset, 0u);
  EXPECT_EQ(set.writes[0].mask, 0x0008u);
  EXPECT_EQ(set.writes[0].raw & set.writes[0].mask, 0x0008u) << "bit 3 set";
  EXPECT_EQ(set.writes[0].metric, "x.3");
  EXPECT_EQ(set.writes[0].value, "true");

  const auto cleared = session.command("X", command_of("x.3", DataType::Boolean, false), model, true);
  ASSERT_EQ(cleared.writes.size(), 1u);
  EXPECT_EQ(cleared.writes[0].mask, 0x0008u);
  EXPECT_EQ(cleared.writes[0].raw & cleared.writes[0].mask, 0u) << "bit 3 cleared, and only it";
  EXPECT_EQ(cleared.writes[0].value, "false");

  // A number is a bit's value too, when it is 0 or 1.
  const auto one = session.command("X", command_of("x.15", DataType::UInt16, integer_value(DataType::UInt16, 1)), model, true);
  ASSERT_EQ(one.writes.size(), 1u);
  EXPECT_EQ(one.writes[0].mask, 0x8000u);
  EXPECT_EQ(one.writes[0].raw & one.writes[0].mask, 0x8000u);
  EXPECT_EQ(session.command("X", command_of("x.15", DataType::UInt16, integer_value(DataType::UInt16, 2)), model, true).refused,
            std::vector<std::string>{"x.15 takes 0…1, not 2"});
  EXPECT_EQ(session.counters().taken, 3u);
  EXPECT_EQ(session.counters().refused, 1u);
}

TEST_F(SparkplugEdgeSession, AStringToABitOfXIsRefusedWithTheReasonAndWritesNothing) {
  auto session = connected_session();
  const auto text = session.command("X", command_of("x.3", DataType::String, std::string("true")), model, true);
  EXPECT_TRUE(text.writes.empty());
  EXPECT_EQ(text.malformed, "x.3 takes a Boolean (or the number 0 or 1), not a String");
  EXPECT_EQ(session.counters().malformed, 1u);
  EXPECT_EQ(session.counters().taken, 0u);
}

// Several metrics of X in one DCMD are as many writes, in the command's order, each of
// its own bits: the word first, then a bit over it, is the word with that bit.
TEST_F(SparkplugEdgeSession, TheWordAndBitsOfXInOneDcmdAreEachAWriteInTheirOrder) {
  auto session = connected_session();
  Payload payload;
  const auto add = [&](std::string name, DataType type, MetricValue value) {
    Metric metric;
    metric.name = std::move(name);
    metric.datatype = type;
    metric.value = std::move(value);
    payload.metrics.push_back(std::move(metric));
  };
  add("x", DataType::UInt16, integer_value(DataType::UInt16, 0x00F0));
  add("x.4", DataType::Boolean, false);
  add("x.0", DataType::Boolean, true);
  const auto command = session.command("X", encoded(payload), model, true);
  ASSERT_EQ(command.writes.size(), 3u);
  std::uint16_t word = 0xFFFF;  // whatever X held before
  for (const auto& write : command.writes) word = static_cast<std::uint16_t>((word & ~write.mask) | (write.raw & write.mask));
  EXPECT_EQ(command.writes[0].metric, "x");
  EXPECT_EQ(command.writes[0].mask, 0xFFFFu);
  EXPECT_EQ(command.writes[1].metric, "x.4");
  EXPECT_EQ(command.writes[2].metric, "x.0");
  EXPECT_EQ(word, 0x00E1u);
}

TEST_F(SparkplugEdgeSession, XsBitsAreBooleanMetricsInTheBirthAndOnlyTheChangedOnesInData) {
  auto session = connected_session();
  const auto births = step(session);
  const auto x_birth = std::find_if(births.begin(), births.end(),
                                    [](const Message& m) { return m.topic == "spBv1.0/plant-7/DBIRTH/bridge-17/X"; });
  ASSERT_NE(x_birth, births.end());
  const auto birth = decoded(*x_birth);
  ASSERT_EQ(birth.metrics.size(), 17u) << "the word and its sixteen bits";
  for (unsigned bit = 0; bit < 16; ++bit) {
    const auto* metric = find(birth, "x." + std::to_string(bit));
    ASSERT_NE(metric, nullptr) << bit;
    EXPECT_EQ(metric->datatype, DataType::Boolean);
    EXPECT_EQ(metric->is_null, true) << "X was never written";
  }

  store.write(BankId::X, 0, 0x0021);
  const auto first = step(session, now_ms + 1);
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0].topic, "spBv1.0/plant-7/DDATA/bridge-17/X");
  EXPECT_EQ(decoded(first[0]).metrics.size(), 17u) << "every bit had no value before";

  store.write(BankId::X, 0, 0x0025);
  const auto second = step(session, now_ms + 2);
  ASSERT_EQ(second.size(), 1u);
  const auto data = decoded(second[0]);
  ASSERT_EQ(data.metrics.size(), 2u) << "the word and bit 2, nothing else";
  ASSERT_NE(find(data, "x"), nullptr);
  const auto* bit2 = find(data, "x.2");
  ASSERT_NE(bit2, nullptr);
  EXPECT_EQ(bit2->datatype, DataType::Boolean);
  EXPECT_EQ(bit2->value, MetricValue(true));
}

// The way back is the value model's (values/value_codec): what would not read back as the
// value written is refused with the reason, and the rest of the command is still taken.
TEST_F(SparkplugEdgeSession, DcmdRefusesWhatWouldNotReadBackAsItselfWithTheReason) {
  auto session = connected_session();
  Payload payload;
  for (const auto& [name, value] : std::vector<std::pair<std::string, double>>{
           {"w_00", 3276.7}, {"w_01", 6553.5}, {"w_02", 12.34}, {"w_03", 3276.6}, {"w_04", -3276.8}, {"w_05", -3276.9}}) {
    Metric metric;
    metric.name = name;
    metric.datatype = DataType::Double;
    metric.value = value;
    payload.metrics.push_back(std::move(metric));
  }
  const auto command = session.command("W", encoded(payload), model, true);
  ASSERT_EQ(command.writes.size(), 2u);
  EXPECT_EQ(command.writes[0].metric, "w_03");
  EXPECT_EQ(command.writes[0].raw, 0x7FFEu);
  EXPECT_EQ(command.writes[1].metric, "w_04");
  EXPECT_EQ(command.writes[1].raw, 0x8000u);
  EXPECT_EQ(command.refused, (std::vector<std::string>{"w_00 = 3276.7 would be the word 0x7FFF, which reads as not measured",
                                                       "w_01 takes -3276.8…3276.6, not 6553.5",
                                                       "w_02 takes steps of 0.1, and 12.34 is between two",
                                                       "w_05 takes -3276.8…3276.6, not -3276.9"}));
  EXPECT_EQ(session.counters().taken, 2u);
  EXPECT_EQ(session.counters().refused, 4u);
}

TEST_F(SparkplugEdgeSession, AFloatIsTheDecimalTheHostWroteNotItsBinaryWidening) {
  auto session = connected_session();
  const auto top = session.command("W", command_of("w_03", DataType::Float, 3276.6f), model, true);
  ASSERT_EQ(top.writes.size(), 1u) << (top.refused.empty() ? "" : top.refused.front());
  EXPECT_EQ(top.writes[0].raw, 32766u);
  const auto tenth = session.command("W", command_of("w_03", DataType::Float, 0.1f), model, true);
  ASSERT_EQ(tenth.writes.size(), 1u);
  EXPECT_EQ(tenth.writes[0].raw, 1u);
  EXPECT_EQ(session.command("W", command_of("w_03", DataType::Float, 12.34f), model, true).refused,
            std::vector<std::string>{"w_03 takes steps of 0.1, and 12.34 is between two"});
}

TEST_F(SparkplugEdgeSession, EveryRefusalSaysWhy) {
  auto session = connected_session();
  EXPECT_EQ(session.command("W", command_of("w_03", DataType::Float, 1.0f), model, false).refused,
            std::vector<std::string>{"w_03: commands are off (sparkplug.commands)"});
  EXPECT_EQ(session.command("W", command_of("w_99", DataType::Float, 1.0f), model, true).refused,
            std::vector<std::string>{"w_99: no metric of W"});
  EXPECT_EQ(session.command("D1", command_of("engine_speed", DataType::UInt16, 1u), model, true).refused,
            std::vector<std::string>{"engine_speed: the bridge takes commands to W and X only"});
  EXPECT_EQ(session.command("", command_of("Node Control/Next Server", DataType::Boolean, true), model, true).refused,
            std::vector<std::string>{"Node Control/Next Server: not a node control the bridge has"});
  EXPECT_EQ(session.counters().refused, 4u);
}

}  // namespace
}  // namespace unima::sparkplug
