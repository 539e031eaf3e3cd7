// report/ (SPEC §21): the `report` section, the deadbands over the value model, the rule of
// a change, the schedule of a bank's documents (min_interval, max_interval) with time
// points passed in, when a bank's values were measured, and the JSON of a scaled number.

#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "mqtt/bank_documents.hpp"
#include "report/change_rule.hpp"
#include "report/deadbands.hpp"
#include "report/measurement_times.hpp"
#include "report/report_schedule.hpp"
#include "tests/support/config_parse_error.hpp"
#include "tests/support/error_message.hpp"
#include "values/store_snapshot.hpp"

namespace unima::report {
namespace {

using namespace std::chrono_literals;
using banks::BankId;
using values::Value;

const std::string report_devices = "devices: { D1: { type: unigen-chp, address: 5 } }\n";

config::Config report_config(const std::string& text) { return config::parse_text(report_devices + text, "r.yaml", {}); }

std::string report_error(const std::string& text) { return test_support::config_parse_error(report_devices + text, "r.yaml"); }

// The ConfigError of the deadbands of `text` over its value model, or "(no error)".
std::string deadbands_error(const std::string& text) {
  const auto config = report_config(text);
  return test_support::error_message<config::ConfigError>([&] { (void)Deadbands(config.report, values::ValueModel(config)); });
}

Value number(double n) { return {n, values::State::ok}; }
Value null_value(values::State why = values::State::not_measured) { return {std::monostate{}, why}; }

TEST(ReportConfig, DefaultsKeepEveryChangeAndTheMqttPeriod) {
  const auto plain = report_config("mqtt: { broker: 'mqtt://x', publish: { period: 30s } }\n");
  EXPECT_EQ(plain.report.min_interval, 100ms);
  EXPECT_FALSE(plain.report.max_interval);
  EXPECT_EQ(config::max_report_interval(plain), 30s) << "max_interval: mqtt.publish.period by default";
  EXPECT_EQ(plain.report.default_deadband, 0);
  EXPECT_TRUE(plain.report.deadbands.empty());
  EXPECT_EQ(config::max_report_interval(report_config("")), 10s) << "without mqtt: its default period";

  const auto c = report_config("report:\n  min_interval: 250ms\n  max_interval: 60s\n  deadband:\n    default: 0.2\n"
                               "    D1.engine_speed: 5\n    D1.oil_temperature: 0.5\n");
  EXPECT_EQ(c.report.min_interval, 250ms);
  EXPECT_EQ(config::max_report_interval(c), 60s);
  EXPECT_DOUBLE_EQ(c.report.default_deadband, 0.2);
  ASSERT_EQ(c.report.deadbands.size(), 2u);
  EXPECT_EQ(c.report.deadbands[0].bank, BankId::D1);
  EXPECT_EQ(c.report.deadbands[0].value, "engine_speed");
  EXPECT_EQ(c.report.deadbands[0].deadband, 5);
  EXPECT_EQ(c.report.deadbands[1].origin, "r.yaml:8:5");
}

TEST(ReportConfig, ErrorsNameTheirPlace) {
  EXPECT_EQ(report_error("report: { deadband: { D2.engine_speed: 5 } }\n"),
            "r.yaml:2:23: report.deadband.D2.engine_speed: D2 is not in this config (no device under devices)");
  EXPECT_EQ(report_error("report: { deadband: { D1.engine_speed: -1 } }\n"),
            "r.yaml:2:40: report.deadband.D1.engine_speed must be 0 or more (in the value's unit)");
  EXPECT_EQ(report_error("report: { deadband: { default: -0.5 } }\n"),
            "r.yaml:2:32: report.deadband.default must be 0 or more (in the value's unit)");
  EXPECT_EQ(report_error("report: { deadband: { engine_speed: 5 } }\n"),
            "r.yaml:2:23: report.deadband.engine_speed: a deadband is named `default` or <bank>.<value>, e.g. D1.engine_speed");
  EXPECT_EQ(report_error("report: { deadband: { W.w_00: 5 } }\n"),
            "r.yaml:2:23: report.deadband.W.w_00: W is not reported (W and X are setpoints)");
  EXPECT_EQ(report_error("report: { min_interval: 2s, max_interval: 1s }\n"),
            "r.yaml:2:25: report.min_interval (2000 ms) is longer than report.max_interval (1000 ms): a full document could "
            "never go when it must");
  EXPECT_EQ(report_error("mqtt: { broker: 'mqtt://x', publish: { period: 1s } }\nreport: { min_interval: 5s }\n"),
            "r.yaml:3:25: report.min_interval (5000 ms) is longer than report.max_interval (1000 ms, mqtt.publish.period): "
            "a full document could never go when it must");
  EXPECT_EQ(report_error("report: { min: 1s }\n").substr(0, 12), "r.yaml:2:11:");
}

TEST(ReportDeadbands, EachValueItsOwnElseTheDefaultAndNoneForBits) {
  const auto config = report_config("report: { deadband: { default: 2, D1.oil_temperature: 0.5 } }\n");
  const values::ValueModel model(config);
  const Deadbands deadbands(config.report, model);
  const auto& layout = *model.bank(BankId::D1);
  const auto of = [&](std::string_view name) {
    for (std::size_t i = 0; i < layout.values.size(); ++i)
      if (layout.values[i].name == name) return deadbands.of(BankId::D1)[i];
    ADD_FAILURE() << name << " is not a value of D1";
    return -1.0;
  };
  EXPECT_EQ(of("oil_temperature"), 0.5);
  EXPECT_EQ(of("engine_speed"), 2) << "the default";
  EXPECT_EQ(of("status"), 0) << "a bit word: every change counts";
  EXPECT_EQ(of("status.power_mode"), 0) << "a bit: every change counts";
  EXPECT_TRUE(Deadbands().of(BankId::D1).empty());

  EXPECT_EQ(deadbands_error("report: { deadband: { D1.no_such_value: 1 } }\n"),
            "r.yaml:2:23: report.deadband.D1.no_such_value: D1 has no value no_such_value (`unima-bridge map` lists them)");
  EXPECT_EQ(deadbands_error("report: { deadband: { D1.status: 1 } }\n"),
            "r.yaml:2:23: report.deadband.D1.status: status is a bit or bit word, whose every change counts; a deadband "
            "is for numbers");
  EXPECT_EQ(deadbands_error("report: { deadband: { D1.engine_speed: 5 } }\n"), "(no error)");
}

TEST(ReportChangeRule, BeyondTheDeadbandNullsBooleansAndText) {
  EXPECT_FALSE(counts_as_changed(number(85.0), number(85.5), 0.5)) << "exactly the deadband is within it";
  EXPECT_TRUE(counts_as_changed(number(85.0), number(85.6), 0.5));
  EXPECT_TRUE(counts_as_changed(number(85.0), number(84.4), 0.5)) << "absolute: down as up";
  EXPECT_TRUE(counts_as_changed(number(85.0), number(85.1), 0)) << "deadband 0: every change";
  EXPECT_FALSE(counts_as_changed(number(85.0), number(85.0), 0));
  EXPECT_TRUE(counts_as_changed(number(85.0), null_value(), 1000)) << "to null";
  EXPECT_TRUE(counts_as_changed(null_value(), number(0), 1000)) << "from null";
  EXPECT_FALSE(counts_as_changed(null_value(), null_value(values::State::offline), 0)) << "null stays null";
  EXPECT_TRUE(counts_as_changed({true, values::State::ok}, {false, values::State::ok}, 5));
  EXPECT_TRUE(counts_as_changed({std::string("AB"), values::State::ok}, {std::string("AC"), values::State::ok}, 5));
}

// A schedule over banks of one value each, whose deadbands are `deadbands`.
struct ScheduledBanks {
  ScheduledBanks(std::vector<std::vector<Value>> values_now, std::vector<double> deadbands_of_values)
      : values(std::move(values_now)), deadbands(std::move(deadbands_of_values)), changes(values.size(), 0) {}

  std::vector<std::vector<Value>> values;
  std::vector<double> deadbands;
  std::vector<std::uint64_t> changes;
  std::vector<std::size_t> asked;

  std::vector<std::size_t> due(ReportSchedule& schedule, ReportSchedule::Clock::time_point now) {
    asked.clear();
    return schedule.due(changes, now, [this](std::size_t i) {
      asked.push_back(i);
      return ReportSchedule::BankNow{values[i], true, std::span(&deadbands[i], 1)};
    });
  }
  void set(std::size_t i, double value) {
    values[i] = {number(value)};
    ++changes[i];
  }
};

const Intervals every_change{.min_interval = 100ms, .max_interval = 10s, .on_change = true};

TEST(ReportSchedule, AllFirstEachAgainAtItsMaxIntervalAndAllAfterAReconnect) {
  ReportSchedule schedule(3, every_change);
  ScheduledBanks banks{{{number(1)}, {number(2)}, {number(3)}}, {0, 0, 0}};
  const auto t0 = ReportSchedule::Clock::now();
  EXPECT_EQ(banks.due(schedule, t0), (std::vector<std::size_t>{0, 1, 2})) << "everything first";
  EXPECT_EQ(schedule.next_due(), t0 + 10s) << "nothing changed: max_interval";
  EXPECT_TRUE(banks.due(schedule, t0 + 5s).empty());
  EXPECT_TRUE(banks.asked.empty()) << "no count moved: no bank read";
  banks.set(1, 20);
  EXPECT_EQ(banks.due(schedule, t0 + 6s), (std::vector<std::size_t>{1}));
  EXPECT_EQ(banks.due(schedule, t0 + 10s), (std::vector<std::size_t>{0, 2}))
      << "max_interval counts from each bank's own last document";
  EXPECT_EQ(schedule.next_due(), t0 + 16s);
  EXPECT_EQ(banks.due(schedule, t0 + 16s), (std::vector<std::size_t>{1})) << "in full, though nothing changed";
  schedule.publish_all();
  EXPECT_EQ(banks.due(schedule, t0 + 16s + 1ms).size(), 3u) << "a reconnect";

  ReportSchedule periodic_only(2, {.min_interval = 100ms, .max_interval = 10s, .on_change = false});
  ScheduledBanks two{{{number(1)}, {number(2)}}, {0, 0}};
  EXPECT_EQ(two.due(periodic_only, t0).size(), 2u);
  two.set(0, 5);
  EXPECT_TRUE(two.due(periodic_only, t0 + 1s).empty()) << "on_change: false";
  EXPECT_EQ(periodic_only.next_due(), t0 + 10s);
}

// The leading edge: a change min_interval after the bank's last document goes at once;
// one sooner waits until min_interval is up and goes then with the values it has then.
TEST(ReportSchedule, MinIntervalHoldsAChangeBackAndItGoesWithTheLatestValues) {
  ReportSchedule schedule(2, {.min_interval = 250ms, .max_interval = 10s, .on_change = true});
  ScheduledBanks banks{{{number(1)}, {number(2)}}, {0, 0}};
  const auto t0 = ReportSchedule::Clock::now();
  banks.due(schedule, t0);
  banks.set(1, 3);
  EXPECT_EQ(banks.due(schedule, t0 + 250ms), (std::vector<std::size_t>{1})) << "min_interval after its last: at once";
  banks.set(1, 4);
  EXPECT_TRUE(banks.due(schedule, t0 + 300ms).empty());
  EXPECT_TRUE(banks.asked.empty()) << "a held-back bank is not even read";
  EXPECT_EQ(schedule.next_due(), t0 + 500ms);
  banks.set(1, 5);
  banks.set(0, 9);
  EXPECT_EQ(banks.due(schedule, t0 + 310ms), (std::vector<std::size_t>{0})) << "each bank has its own min_interval";
  EXPECT_TRUE(banks.due(schedule, t0 + 499ms).empty());
  EXPECT_EQ(banks.due(schedule, t0 + 500ms), (std::vector<std::size_t>{1}));
  EXPECT_TRUE(banks.due(schedule, t0 + 500ms).empty()) << "once, with 5, not once per change";
}

// A move within the deadband is no change: nothing goes, and the next comparison is still
// against what was published, so small steps that add up beyond it do go.
TEST(ReportSchedule, MovesWithinTheDeadbandAreComparedWithWhatWasPublished) {
  ReportSchedule schedule(1, every_change);
  ScheduledBanks banks{{{number(85.0)}}, {0.5}};
  const auto t0 = ReportSchedule::Clock::now();
  banks.due(schedule, t0);
  banks.set(0, 85.3);
  EXPECT_TRUE(banks.due(schedule, t0 + 1s).empty()) << "0.3 < 0.5";
  EXPECT_EQ(banks.asked.size(), 1u);
  banks.set(0, 85.5);
  EXPECT_TRUE(banks.due(schedule, t0 + 2s).empty()) << "0.5 from 85.0 is within it";
  banks.set(0, 85.6);
  EXPECT_EQ(banks.due(schedule, t0 + 3s), (std::vector<std::size_t>{0})) << "0.6 from 85.0, in steps of 0.3 at most";
  banks.set(0, 85.9);
  EXPECT_TRUE(banks.due(schedule, t0 + 4s).empty()) << "0.3 from the 85.6 published";
  EXPECT_EQ(schedule.next_due(), t0 + 13s) << "held back by the deadband, it goes at max_interval";
  EXPECT_EQ(banks.due(schedule, t0 + 13s), (std::vector<std::size_t>{0}));
}

TEST(ReportSchedule, ANullAndTheOnLineStateAlwaysCount) {
  ReportSchedule schedule(1, every_change);
  std::vector<Value> values{number(85.0)};
  bool online = true;
  std::vector<std::uint64_t> changes{0};
  const std::vector<double> deadband{1000};
  const auto bank_now = [&](std::size_t) { return ReportSchedule::BankNow{values, online, deadband}; };
  const auto t0 = ReportSchedule::Clock::now();
  schedule.due(changes, t0, bank_now);
  values = {null_value()};
  ++changes[0];
  EXPECT_EQ(schedule.due(changes, t0 + 1s, bank_now).size(), 1u) << "to null, whatever the deadband";
  values = {null_value(values::State::offline)};
  online = false;
  ++changes[0];
  EXPECT_EQ(schedule.due(changes, t0 + 2s, bank_now).size(), 1u) << "off line";
  values = {number(85.0)};
  online = true;
  ++changes[0];
  EXPECT_EQ(schedule.due(changes, t0 + 3s, bank_now).size(), 1u) << "from null, and on line again";
}

// republish(): a bank goes again, changed or not, when its min_interval allows (Sparkplug
// tells the host a value a refused command left as it was); went_in_full() tells a
// max_interval's document from a change's.
TEST(ReportSchedule, ARepublishedBankGoesWhenItsMinIntervalAllowsAndFullIsTold) {
  ReportSchedule schedule(2, {.min_interval = 250ms, .max_interval = 10s, .on_change = true});
  ScheduledBanks banks{{{number(1)}, {number(2)}}, {0, 0}};
  const auto t0 = ReportSchedule::Clock::now();
  banks.due(schedule, t0);
  EXPECT_TRUE(schedule.went_in_full(0)) << "its first document";
  schedule.republish(1);
  EXPECT_TRUE(banks.due(schedule, t0 + 100ms).empty());
  EXPECT_EQ(schedule.next_due(), t0 + 250ms);
  EXPECT_EQ(banks.due(schedule, t0 + 250ms), (std::vector<std::size_t>{1})) << "unchanged, but asked for";
  EXPECT_FALSE(schedule.went_in_full(1));
  EXPECT_TRUE(banks.due(schedule, t0 + 600ms).empty()) << "once";
  banks.set(0, 5);
  EXPECT_EQ(banks.due(schedule, t0 + 1s), (std::vector<std::size_t>{0}));
  EXPECT_FALSE(schedule.went_in_full(0)) << "for a change";
  EXPECT_EQ(banks.due(schedule, t0 + 10250ms), (std::vector<std::size_t>{1}));
  EXPECT_TRUE(schedule.went_in_full(1)) << "its max_interval";
}

TEST(ReportMeasurementTimes, ABankKeepsTheTimeOfItsLastChange) {
  MeasurementTimes times;
  const auto t0 = std::chrono::system_clock::time_point{} + 1000h;
  const std::vector<std::uint64_t> first{0, 0};
  times.note(first, t0);
  EXPECT_EQ(times.of(0), t0) << "first seen";
  const std::vector<std::uint64_t> one_changed{0, 1};
  times.note(one_changed, t0 + 5s);
  EXPECT_EQ(times.of(0), t0) << "unchanged: its time stays, however late it is re-sent";
  EXPECT_EQ(times.of(1), t0 + 5s);
  times.note(one_changed, t0 + 9s);
  EXPECT_EQ(times.of(1), t0 + 5s) << "the same count: no new measurement";
  const std::vector<std::uint64_t> three{0, 1, 0};
  times.note(three, t0 + 10s);
  EXPECT_EQ(times.of(2), t0 + 10s) << "another layout starts again";
}

// SPEC §21: a number never changes its JSON type — a scaled value has a fraction part even
// when it is whole, an integer never has one — and the document's time is the measurement's.
TEST(ReportDocuments, AScaledWholeNumberKeepsItsFractionAndTheTimeIsTheMeasurement) {
  const auto config = report_config("");
  const values::ValueModel model(config);
  banks::RegisterStore store(config::bank_shapes(config));
  store.set_online(BankId::D1, true);
  const std::vector<std::uint16_t> speed = {1500};
  store.store_telegram(BankId::D1, 1, speed);
  const std::vector<std::uint16_t> oil = {850};
  store.store_telegram(BankId::D1, 0x21, oil);
  const auto measured = std::chrono::sys_days{std::chrono::year{2026} / 11 / 29} + 12h + 1min + 2s + 345ms;
  const auto document = mqtt::bank_document(*model.bank(BankId::D1), model.evaluate(BankId::D1, values::snapshot_of(store)),
                                            true, measured);
  EXPECT_EQ(document["oil_temperature"].dump(), "85.0") << document.dump();
  EXPECT_EQ(document["engine_speed"].dump(), "1500") << document.dump();
  EXPECT_EQ(document["time"], "2026-11-29T12:01:02.345000Z");
}

}  // namespace
}  // namespace unima::report
