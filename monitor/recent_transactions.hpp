#pragma once
// The last transactions of every port, kept for the front page (SPEC §13): its monitor
// pane shows them through a filter of its own, which may differ from the log's. Kept as
// bytes and formatted only when a page asks, so that a busy port pays one copy per
// transaction and no formatting. Pure: no clock, no I/O.

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "modbus/transaction.hpp"
#include "monitor/command_filter.hpp"

namespace unima::monitor {

class RecentTransactions {
 public:
  explicit RecentTransactions(std::size_t capacity = 256);

  void push(const modbus::Transaction& transaction, std::uint8_t ix);

  /// The number the next transaction pushed will carry; numbers start at 0 and never repeat.
  std::uint64_t next_number() const { return next_; }

  struct Lines {
    std::vector<std::string> lines;  // monitor lines (text format, without "\n"), oldest first
    std::uint64_t skipped = 0;       // passing the filter, but older than the newest `limit` or already gone
    std::uint64_t next = 0;          // where the next call goes on
  };
  /// The lines of the transactions numbered `from` and later that pass `filter`, the
  /// newest `limit` of them.
  Lines since(std::uint64_t from, const CommandFilter& filter, std::size_t limit) const;

 private:
  struct Entry {
    std::uint64_t number = 0;
    modbus::PortKind port = modbus::PortKind::tcp;
    std::string peer;
    std::string line;
    std::chrono::system_clock::time_point time;
    modbus::TransactionState state = modbus::TransactionState::done;
    std::uint8_t ix = 0;
    std::vector<std::uint8_t> query;     // capacity kept between uses: no allocation once warm
    std::vector<std::uint8_t> response;
  };
  bool passes(const Entry& entry, const CommandFilter& filter) const;
  std::string line(const Entry& entry) const;

  std::vector<Entry> ring_;
  std::uint64_t next_ = 0;
};

}  // namespace unima::monitor
