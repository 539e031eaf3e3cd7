// The front page's live feed (web/live_view): the whole picture for a page that opens,
// then only what changed; the monitor pane's lines through each page's own filter
// (monitor/recent_transactions); and which files the page is served from (web/).
// In-process, without the daemon; among the integration tests because app/ links io/.

#include <gtest/gtest.h>

#include <array>

#include "web/live_view.hpp"
#include "monitor/recent_transactions.hpp"
#include "web/page_files.hpp"

namespace unima::web {
namespace {

class RecordingSink : public web::EventSink {
 public:
  bool send(std::string_view events) override {
    if (closed_) return false;
    sent += events;
    return true;
  }
  bool closed() const override { return closed_; }
  void close() { closed_ = true; }
  /// What was sent since the last call.
  std::string take() { return std::exchange(sent, {}); }

  std::string sent;

 private:
  bool closed_ = false;
};

LiveSnapshot snapshot(std::optional<std::uint16_t> a, std::optional<std::uint16_t> b, bool online = false) {
  return {nlohmann::json{{"devices", {{{"bank", "D1"}, {"online", online}}}}}, {0x1100, 0x1101}, {a, b}, {}};
}

// An FC4 read of `quantity` registers from `start` by a TCP client: MBAP + PDU.
std::vector<std::uint8_t> fc4(std::uint16_t start, std::uint16_t quantity, std::uint8_t function = 4) {
  return {0x00, 0x01, 0x00, 0x00, 0x00, 0x06, 0x01, function, static_cast<std::uint8_t>(start >> 8),
          static_cast<std::uint8_t>(start), static_cast<std::uint8_t>(quantity >> 8), static_cast<std::uint8_t>(quantity)};
}

void push(monitor::RecentTransactions& recent, const std::vector<std::uint8_t>& query, std::uint8_t ix) {
  modbus::Transaction t;
  t.port = modbus::PortKind::tcp;
  t.peer = "127.0.0.1:40000";
  t.query = query;
  recent.push(t, ix);
}

TEST(LiveView, APageGetsEverythingFirstThenOnlyWhatChanged) {
  LiveView view;
  monitor::RecentTransactions recent;
  auto page = std::make_shared<RecordingSink>();
  view.subscribe(page, {}, snapshot(0x7FFF, 12), recent);
  const auto first = page->take();
  EXPECT_NE(first.find("event: panel\ndata: {\"devices\":[{\"bank\":\"D1\",\"online\":false}]}\n\n"), std::string::npos) << first;
  EXPECT_NE(first.find("event: registers\ndata: {\"0x1100\":32767,\"0x1101\":12}\n\n"), std::string::npos) << first;

  view.update(snapshot(0x7FFF, 12), recent);
  EXPECT_EQ(page->take(), "") << "nothing changed, nothing sent";

  view.update(snapshot(0x7FFF, 13, true), recent);
  EXPECT_EQ(page->take(), "event: registers\ndata: {\"0x1101\":13}\n\n"
                          "event: panel\ndata: {\"devices\":[{\"bank\":\"D1\",\"online\":true}]}\n\n");
  view.update(snapshot(std::nullopt, 13, true), recent);
  EXPECT_EQ(page->take(), "event: registers\ndata: {\"0x1100\":null}\n\n");
}

// The value model's values (values/) go to the page like the raw registers: all of them
// first, then only those that changed, each with the state the page shows in words.
TEST(LiveView, NamedValuesGoFirstInFullThenOnlyThoseThatChanged) {
  const auto with_values = [](nlohmann::json speed, std::string state) {
    LiveSnapshot s{nlohmann::json::object(), {0x1101}, {1}, {}};
    s.named_banks = {std::make_shared<const NamedValues>(NamedValues{{"D1/engine_speed", {{"value", speed}, {"state", state}}}}),
                     std::make_shared<const NamedValues>(
                         NamedValues{{"W/w_00", {{"value", nullptr}, {"state", "not set"}, {"set", false}}}})};
    return s;
  };
  LiveView view;
  monitor::RecentTransactions recent;
  auto page = std::make_shared<RecordingSink>();
  view.subscribe(page, {}, with_values(1500, "ok"), recent);
  const auto first = page->take();
  EXPECT_NE(first.find("event: values\ndata: {\"D1/engine_speed\":{\"state\":\"ok\",\"value\":1500},"
                       "\"W/w_00\":{\"set\":false,\"state\":\"not set\",\"value\":null}}\n\n"),
            std::string::npos)
      << first;
  view.update(with_values(nullptr, "off-line"), recent);
  EXPECT_EQ(page->take(), "event: values\ndata: {\"D1/engine_speed\":{\"state\":\"off-line\",\"value\":null}}\n\n");
  view.update(with_values(nullptr, "off-line"), recent);
  EXPECT_EQ(page->take(), "");
}

// A bank that did not change is the same object in the next snapshot (HttpAnswers keeps
// it while the store's count of the bank's changes stays): only the banks that are new
// objects are looked at, and of them only the values that differ are sent.
TEST(LiveView, OnlyTheBanksThatAreNewObjectsAreCompared) {
  const auto bank = [](std::string key, int value) {
    return std::make_shared<const NamedValues>(NamedValues{{std::move(key), {{"value", value}, {"state", "ok"}}}});
  };
  const auto s1 = bank("S1/power", 7);
  const auto snapshot_with = [&](std::shared_ptr<const NamedValues> d1) {
    LiveSnapshot s{nlohmann::json::object(), {0x1101}, {1}, {}};
    s.named_banks = {std::move(d1), s1};
    return s;
  };
  LiveView view;
  monitor::RecentTransactions recent;
  auto page = std::make_shared<RecordingSink>();
  view.subscribe(page, {}, snapshot_with(bank("D1/engine_speed", 1500)), recent);
  page->take();
  view.update_values(snapshot_with(bank("D1/engine_speed", 1500)));
  EXPECT_EQ(page->take(), "") << "a new object with the same values sends nothing";
  view.update_values(snapshot_with(bank("D1/engine_speed", 1501)));
  EXPECT_EQ(page->take(), "event: values\ndata: {\"D1/engine_speed\":{\"state\":\"ok\",\"value\":1501}}\n\n");
  LiveSnapshot renamed{nlohmann::json::object(), {0x1101}, {1}, {}};
  renamed.named_banks = {bank("D1/speed", 1501), s1};
  view.update(renamed, recent);
  EXPECT_NE(page->take().find("event: layout"), std::string::npos) << "a bank whose names changed is a new layout";
}

// A page that opens between two snapshots gets the last one, so that a value which
// changed and changed back before the next is not left showing the middle value.
TEST(LiveView, ALatePageStartsFromTheLastSnapshotSoTheChangesAfterAreExact) {
  LiveView view;
  monitor::RecentTransactions recent;
  auto early = std::make_shared<RecordingSink>();
  view.subscribe(early, {}, snapshot(1, 1), recent);
  auto late = std::make_shared<RecordingSink>();
  view.subscribe(late, {}, snapshot(2, 1), recent);  // 0x1100 is 2 for a moment
  EXPECT_NE(late->take().find("{\"0x1100\":1,\"0x1101\":1}"), std::string::npos);
  view.update(snapshot(1, 1), recent);  // and 1 again at the next snapshot
  EXPECT_EQ(late->take(), "");
}

TEST(LiveView, AClosedPageIsForgottenAndALayoutChangeSendsEverything) {
  LiveView view;
  monitor::RecentTransactions recent;
  auto gone = std::make_shared<RecordingSink>();
  auto stays = std::make_shared<RecordingSink>();
  view.subscribe(gone, {}, snapshot(1, 1), recent);
  view.subscribe(stays, {}, snapshot(1, 1), recent);
  stays->take();
  gone->close();
  view.update(snapshot(1, 2), recent);
  EXPECT_EQ(view.pages(), 1u);
  stays->take();

  LiveSnapshot reloaded{nlohmann::json::object(), {0x2000}, {7}, {}};
  view.update(reloaded, recent);
  const auto events = stays->take();
  EXPECT_TRUE(events.starts_with("event: layout\ndata: {}\n\n")) << events;
  EXPECT_NE(events.find("event: registers\ndata: {\"0x2000\":7}\n\n"), std::string::npos) << events;
}

// Between heartbeats the values go alone (HttpService, on the leading edge): registers and
// named values that changed, no panel, no monitor lines; a new layout waits for the
// heartbeat's full update.
TEST(LiveView, ValuesAloneCarryTheChangedRegistersAndKeepThePanelForTheHeartbeat) {
  LiveView view;
  monitor::RecentTransactions recent;
  auto page = std::make_shared<RecordingSink>();
  view.subscribe(page, {}, snapshot(1, 1), recent);
  page->take();
  push(recent, fc4(0x1100, 1), 1);
  view.update_values(snapshot(1, 2, true));
  EXPECT_EQ(page->take(), "event: registers\ndata: {\"0x1101\":2}\n\n") << "no panel, no monitor line";
  view.update_values(snapshot(1, 2, true));
  EXPECT_EQ(page->take(), "");
  view.update(snapshot(1, 2, true), recent);
  const auto beat = page->take();
  EXPECT_NE(beat.find("event: panel\ndata: {\"devices\":[{\"bank\":\"D1\",\"online\":true}]}"), std::string::npos)
      << "the heartbeat still sends the panel that changed: " << beat;
  EXPECT_EQ(beat.find("event: registers"), std::string::npos) << "the register went already";
  EXPECT_NE(beat.find("event: monitor"), std::string::npos);

  view.update_values(LiveSnapshot{nlohmann::json::object(), {0x2000}, {7}, {}});
  EXPECT_EQ(page->take(), "") << "a new layout is the heartbeat's";
  view.update(LiveSnapshot{nlohmann::json::object(), {0x2000}, {7}, {}}, recent);
  EXPECT_TRUE(page->take().starts_with("event: layout"));
}

TEST(LiveView, MonitorLinesGoThroughEachPagesOwnFilter) {
  LiveView view;
  monitor::RecentTransactions recent;
  auto all = std::make_shared<RecordingSink>();
  auto only_fn3 = std::make_shared<RecordingSink>();
  view.subscribe(all, {}, snapshot(1, 1), recent);
  view.subscribe(only_fn3, monitor::parse_command_filter("fn=3"), snapshot(1, 1), recent);
  all->take();
  only_fn3->take();
  const auto read4 = fc4(0x1100, 2);
  const auto read3 = fc4(0x0200, 1, 3);
  push(recent, read4, 7);
  push(recent, read3, 8);
  view.update(snapshot(1, 1), recent);
  const auto both = all->take();
  EXPECT_NE(both.find("Ix=7"), std::string::npos) << both;
  EXPECT_NE(both.find("Ix=8"), std::string::npos) << both;
  const auto one = only_fn3->take();
  EXPECT_EQ(one.find("Ix=7"), std::string::npos) << one;
  EXPECT_NE(one.find("tcp:127.0.0.1:40000 Ix=8"), std::string::npos) << one;
  EXPECT_NE(one.find("PDU=03 02 00 00 01"), std::string::npos) << one;
}

// A busy port makes thousands of lines a second; a page gets the newest few of each
// event and how many it did not get.
TEST(LiveView, ABusyPortSendsTheNewestLinesAndCountsTheRest) {
  LiveView view;
  monitor::RecentTransactions recent;
  auto page = std::make_shared<RecordingSink>();
  view.subscribe(page, {}, snapshot(1, 1), recent);
  page->take();
  const auto read = fc4(0x1100, 1);
  for (int i = 0; i < 40; ++i) push(recent, read, static_cast<std::uint8_t>(i));
  view.update(snapshot(1, 1), recent);
  const auto event = page->take();
  const auto data = nlohmann::json::parse(event.substr(event.find("data: ") + 6));
  ASSERT_EQ(data["lines"].size(), LiveView::lines_per_event);
  EXPECT_EQ(data["skipped"], 40 - LiveView::lines_per_event);
  EXPECT_NE(std::string(data["lines"].back()).find("Ix=39 "), std::string::npos) << data.dump();
}

TEST(RecentTransactions, KeepsTheLastOnesAndCountsWhatAPageMissed) {
  monitor::RecentTransactions recent(4);
  const auto read = fc4(0x1100, 1);
  for (std::uint8_t ix = 0; ix < 10; ++ix) push(recent, read, ix);
  EXPECT_EQ(recent.next_number(), 10u);
  const auto lines = recent.since(0, {}, 100);
  ASSERT_EQ(lines.lines.size(), 4u);
  EXPECT_EQ(lines.skipped, 6u);
  EXPECT_NE(lines.lines[0].find("Ix=6 "), std::string::npos) << lines.lines[0];
  EXPECT_EQ(lines.lines[0].find('\n'), std::string::npos);
  EXPECT_EQ(lines.next, 10u);
  const auto newest = recent.since(8, {}, 1);
  ASSERT_EQ(newest.lines.size(), 1u);
  EXPECT_EQ(newest.skipped, 1u);
  EXPECT_NE(newest.lines[0].find("Ix=9 "), std::string::npos);
  EXPECT_TRUE(recent.since(10, {}, 100).lines.empty());
}

TEST(PageFiles, ServesTheEmbeddedFilesByNameAndNothingElse) {
  const auto index = web::served_file("/");
  ASSERT_TRUE(index);
  EXPECT_EQ(index->content_type, "text/html; charset=utf-8");
  EXPECT_NE(index->text.find("<script src=\"/panel.js\""), std::string_view::npos);
  ASSERT_TRUE(web::served_file("/panel.js"));
  EXPECT_EQ(web::served_file("/panel.js")->content_type, "text/javascript; charset=utf-8");
  EXPECT_EQ(web::served_file("/panel.css")->content_type, "text/css; charset=utf-8");
  for (const auto* path : {"", "panel.js", "/../panel.js", "/panel.js/", "/web/panel.js", "/CMakeLists.txt"})
    EXPECT_FALSE(web::served_file(path)) << path;
}

}  // namespace
}  // namespace unima::web
