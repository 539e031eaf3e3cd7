#pragma once
// The front page's live feed (SPEC §13, /api/events): server-sent events that carry only
// what changed. HttpService takes a snapshot on each heartbeat while a page listens, and
// of the values alone when the banks change (on the leading edge, values/leading_edge);
// this compares it with the last one and sends each page
//   event: registers  {"0x1100": 1234, "0x1101": null, ...}  the raw registers that changed
//   event: values     {"D1/engine_speed": {"value": 1234, "state": "ok"}, ...}
//                                                          the values (values/) that changed
//   event: panel      {...}                                  the LEDs, devices, indicators, when changed
//   event: monitor    {"lines": [...], "skipped": n}         new monitor lines through the page's filter
//   event: layout     {}                                     the register map changed (a reload): fetch it again
// A page that subscribes gets the last snapshot in full, so that the changes after it
// are exact. Pure apart from the sinks it writes to: no clock, no Asio.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "web/event_sink.hpp"
#include "monitor/command_filter.hpp"
#include "monitor/recent_transactions.hpp"

namespace unima::web {

/// One bank's values (values/) by "<bank>/<name>", each {"value", "state"} as the page
/// shows it.
using NamedValues = std::vector<std::pair<std::string, nlohmann::json>>;

struct LiveSnapshot {
  nlohmann::json panel;                                   // what the front panel shows
  std::vector<std::uint16_t> addresses;                   // every served register, in address order
  std::vector<std::optional<std::uint16_t>> values;       // nullopt: unreadable (a write bank)
  /// The value model's values, bank by bank. A bank that did not change since the last
  /// snapshot is the same object as there (shared, never altered), so it is neither
  /// rendered nor compared again: the page's stream costs what changed, not the model.
  std::vector<std::shared_ptr<const NamedValues>> named_banks;
};

class LiveView {
 public:
  /// Monitor lines a page gets at most: the last ones when it opens, then per event (four
  /// a second: more than anyone reads, less than a busy port makes — the rest is counted).
  static constexpr std::size_t first_lines = 100;
  static constexpr std::size_t lines_per_event = 25;

  /// Starts `sink`'s feed: the panel, every value, the last monitor lines through `filter`.
  /// `now` becomes the base of the next changes when no page listened before.
  void subscribe(std::shared_ptr<web::EventSink> sink, monitor::CommandFilter filter, LiveSnapshot now,
                 const monitor::RecentTransactions& recent);
  /// Sends every page what changed since the last snapshot; forgets closed pages.
  void update(LiveSnapshot now, const monitor::RecentTransactions& recent);
  /// The same for the registers and values alone (`now.panel` is not looked at): a value's
  /// change goes out at once, the panel and the monitor lines keep the heartbeat's pace.
  /// A changed layout waits for the heartbeat's update, which says so.
  void update_values(LiveSnapshot now);
  bool listened() const { return !pages_.empty(); }
  std::size_t pages() const { return pages_.size(); }

 private:
  struct Page {
    std::shared_ptr<web::EventSink> sink;
    monitor::CommandFilter filter;
    std::uint64_t next_line = 0;
  };
  static std::string monitor_event(Page& page, const monitor::RecentTransactions& recent);

  std::optional<LiveSnapshot> last_;
  std::vector<Page> pages_;
};

/// "event: <name>\ndata: <json>\n\n"
std::string sse_event(std::string_view name, const nlohmann::json& data);

}  // namespace unima::web
