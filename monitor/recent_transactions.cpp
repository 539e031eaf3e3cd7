#include "monitor/recent_transactions.hpp"

#include <algorithm>

#include "modbus/adu_view.hpp"
#include "monitor/monitor_line.hpp"

namespace unima::monitor {

RecentTransactions::RecentTransactions(std::size_t capacity) : ring_(std::max<std::size_t>(capacity, 1)) {}

void RecentTransactions::push(const modbus::Transaction& t, std::uint8_t ix) {
  auto& entry = ring_[next_ % ring_.size()];
  entry.number = next_++;
  entry.port = t.port;
  entry.peer.assign(t.peer);
  entry.line.assign(t.line);
  entry.time = t.time;
  entry.state = t.state;
  entry.ix = ix;
  entry.query.assign(t.query.begin(), t.query.end());
  entry.response.assign(t.response.begin(), t.response.end());
}

bool RecentTransactions::passes(const Entry& entry, const CommandFilter& filter) const {
  if (filter.passes_everything()) return true;
  const modbus::Transaction t{entry.port, entry.peer, entry.time, entry.state, entry.query, entry.response};
  const auto query = modbus::view_adu(entry.query, modbus::framing_of(t));
  return filter.matches(query.address, query.pdu);
}

std::string RecentTransactions::line(const Entry& entry) const {
  const modbus::Transaction t{entry.port, entry.peer, entry.time, entry.state, entry.query, entry.response};
  std::string port;
  append_port_name(port, entry.port, entry.peer, entry.line);
  std::string out;
  append_monitor_line(out, monitor_fields(t, entry.ix, port), MonitorFormat::text);
  if (!out.empty() && out.back() == '\n') out.pop_back();
  return out;
}

RecentTransactions::Lines RecentTransactions::since(std::uint64_t from, const CommandFilter& filter, std::size_t limit) const {
  Lines result;
  result.next = next_;
  const std::uint64_t oldest_kept = next_ > ring_.size() ? next_ - ring_.size() : 0;
  if (from < oldest_kept) {
    result.skipped = oldest_kept - from;  // gone before anyone asked: counted whatever the filter
    from = oldest_kept;
  }
  std::vector<const Entry*> passing;
  for (auto number = from; number < next_; ++number) {
    const auto& entry = ring_[number % ring_.size()];
    if (passes(entry, filter)) passing.push_back(&entry);
  }
  if (passing.size() > limit) {
    result.skipped += passing.size() - limit;
    passing.erase(passing.begin(), passing.end() - static_cast<std::ptrdiff_t>(limit));
  }
  for (const auto* entry : passing) result.lines.push_back(line(*entry));
  return result;
}

}  // namespace unima::monitor
