#include "web/live_view.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace unima::web {

namespace {

std::string address_key(std::uint16_t address) { return fmt::format("0x{:04X}", address); }

nlohmann::json value_json(const std::optional<std::uint16_t>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

nlohmann::json all_values(const LiveSnapshot& snapshot) {
  auto values = nlohmann::json::object();
  for (std::size_t i = 0; i < snapshot.addresses.size(); ++i) values[address_key(snapshot.addresses[i])] = value_json(snapshot.values[i]);
  return values;
}

nlohmann::json changed_values(const LiveSnapshot& before, const LiveSnapshot& now) {
  auto values = nlohmann::json::object();
  for (std::size_t i = 0; i < now.addresses.size(); ++i)
    if (now.values[i] != before.values[i]) values[address_key(now.addresses[i])] = value_json(now.values[i]);
  return values;
}

nlohmann::json all_named(const LiveSnapshot& snapshot) {
  auto values = nlohmann::json::object();
  for (const auto& bank : snapshot.named_banks)
    for (const auto& [key, value] : *bank) values[key] = value;
  return values;
}

// Precondition: same_layout(before, now).
nlohmann::json changed_named(const LiveSnapshot& before, const LiveSnapshot& now) {
  auto values = nlohmann::json::object();
  for (std::size_t b = 0; b < now.named_banks.size(); ++b) {
    if (now.named_banks[b] == before.named_banks[b]) continue;
    const auto& was = *before.named_banks[b];
    const auto& is = *now.named_banks[b];
    for (std::size_t i = 0; i < is.size(); ++i)
      if (is[i].second != was[i].second) values[is[i].first] = is[i].second;
  }
  return values;
}

bool same_keys(const NamedValues& a, const NamedValues& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const auto& x, const auto& y) { return x.first == y.first; });
}

bool same_layout(const LiveSnapshot& a, const LiveSnapshot& b) {
  return a.addresses == b.addresses &&
         std::equal(a.named_banks.begin(), a.named_banks.end(), b.named_banks.begin(), b.named_banks.end(),
                    [](const auto& x, const auto& y) { return x == y || same_keys(*x, *y); });
}

}  // namespace

std::string sse_event(std::string_view name, const nlohmann::json& data) {
  // dump() escapes every line break inside strings, so the data is one line, as SSE needs.
  return fmt::format("event: {}\ndata: {}\n\n", name, data.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

std::string LiveView::monitor_event(Page& page, const monitor::RecentTransactions& recent) {
  auto lines = recent.since(page.next_line, page.filter, lines_per_event);
  page.next_line = lines.next;
  if (lines.lines.empty() && lines.skipped == 0) return {};
  return sse_event("monitor", {{"lines", lines.lines}, {"skipped", lines.skipped}});
}

void LiveView::subscribe(std::shared_ptr<web::EventSink> sink, monitor::CommandFilter filter, LiveSnapshot now,
                         const monitor::RecentTransactions& recent) {
  if (!last_) last_ = std::move(now);
  Page page{std::move(sink), filter, 0};
  // The last lines, not the whole ring: a page opens on the present.
  const auto first = recent.next_number() > first_lines ? recent.next_number() - first_lines : 0;
  page.next_line = first;
  std::string events = sse_event("panel", last_->panel) + sse_event("registers", all_values(*last_)) +
                       sse_event("values", all_named(*last_));
  auto lines = recent.since(page.next_line, page.filter, first_lines);
  page.next_line = lines.next;
  events += sse_event("monitor", {{"lines", lines.lines}, {"skipped", 0}});
  if (page.sink->send(events)) pages_.push_back(std::move(page));
}

void LiveView::update(LiveSnapshot now, const monitor::RecentTransactions& recent) {
  std::string shared;  // what every page gets alike
  if (!last_ || !same_layout(*last_, now)) {
    shared += sse_event("layout", nlohmann::json::object());
    shared += sse_event("registers", all_values(now));
    shared += sse_event("values", all_named(now));
    shared += sse_event("panel", now.panel);
  } else {
    if (auto changes = changed_values(*last_, now); !changes.empty()) shared += sse_event("registers", changes);
    if (auto changes = changed_named(*last_, now); !changes.empty()) shared += sse_event("values", changes);
    if (now.panel != last_->panel) shared += sse_event("panel", now.panel);
  }
  last_ = std::move(now);
  for (auto& page : pages_) {
    const auto events = shared + monitor_event(page, recent);
    if (!events.empty()) page.sink->send(events);
  }
  std::erase_if(pages_, [](const Page& page) { return page.sink->closed(); });
  if (pages_.empty()) last_.reset();  // the next page starts from a fresh snapshot
}

void LiveView::update_values(LiveSnapshot now) {
  if (!last_ || !same_layout(*last_, now)) return;
  std::string shared;
  if (auto changes = changed_values(*last_, now); !changes.empty()) shared += sse_event("registers", changes);
  if (auto changes = changed_named(*last_, now); !changes.empty()) shared += sse_event("values", changes);
  now.panel = std::move(last_->panel);
  last_ = std::move(now);
  if (shared.empty()) return;
  for (auto& page : pages_) page.sink->send(shared);
  std::erase_if(pages_, [](const Page& page) { return page.sink->closed(); });
  if (pages_.empty()) last_.reset();
}

}  // namespace unima::web
