#pragma once
// The bridge's monitor (SPEC §5, seed 004 §8): every port hands each transaction to
// observe() — the SlaveContext::on_transaction hook — which counts it, feeds the capture
// indicators, and queues a line for the log when it passes the command filter. Ix counts
// every transaction of every port (filtered and dropped ones leave gaps).
// observe() runs on the event-loop thread, like the status requests that read the
// counters; only the log writer has a thread of its own (monitor/monitor_writer.hpp).

#include <array>
#include <chrono>
#include <memory>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "monitor/monitor_config.hpp"
#include "monitor/monitor_writer.hpp"
#include "monitor/capture_indicators.hpp"
#include "monitor/command_filter.hpp"
#include "monitor/recent_transactions.hpp"
#include "modbus/transaction.hpp"
#include "modbus/transaction_counters.hpp"

namespace unima::monitor {

class Monitor {
 public:
  /// Throws std::runtime_error when the log file cannot be opened.
  explicit Monitor(const MonitorConfig& config);

  /// The log writer of `config`, or null when it logs nowhere; throws like the constructor.
  static std::unique_ptr<MonitorWriter> make_writer(const MonitorConfig& config);
  /// True when `a` and `b` write the same log the same way (a reload keeps the writer).
  static bool same_log(const MonitorConfig& a, const MonitorConfig& b);
  /// Switches to `config` (a reload). `writer` is make_writer(config) when the log changed
  /// (built beforehand, as it can fail), ignored otherwise. Indicators that stay keep
  /// their readings; counters and Ix go on.
  void reconfigure(const MonitorConfig& config, std::unique_ptr<MonitorWriter> writer);

  void observe(const modbus::Transaction& transaction);
  /// The bridge put a Modbus frame on a line: a slave port's own response (observe() takes
  /// it from Transaction::answered_by_bridge) or a query of the master, which its port
  /// reports when it sends it. The Modbus LED shows these and nothing the bridge only
  /// hears (SPEC §8).
  void frame_sent(std::chrono::system_clock::time_point time);

  const MonitorConfig& config() const { return config_; }
  const monitor::CommandFilter& filter() const { return filter_; }
  const monitor::CaptureIndicators& indicators() const { return indicators_; }
  /// A port's transactions; a line's (`line`: its name as Transaction::line carries it)
  /// when the bridge has several (SPEC §18).
  const modbus::TransactionCounters& counters(modbus::PortKind port, std::string_view line = {}) const;
  /// When the bridge last sent a frame (wall clock: the one ports stamp with), and how many.
  std::optional<std::chrono::system_clock::time_point> last_frame_sent() const { return last_frame_sent_; }
  std::uint64_t frames_sent() const { return frames_sent_; }
  /// The last transactions of every port, whatever the filter (the front page's monitor pane).
  const RecentTransactions& recent() const { return recent_; }
  bool logging() const { return writer_ != nullptr; }
  std::uint64_t dropped() const { return dropped_before_ + (writer_ ? writer_->dropped() : 0); }
  std::uint64_t written() const { return written_before_ + (writer_ ? writer_->written() : 0); }

 private:
  void replace_writer(std::unique_ptr<MonitorWriter> writer);
  using PortCounters = std::array<modbus::TransactionCounters, 5>;  // by PortKind
  PortCounters& counters_of(std::string_view line);

  MonitorConfig config_;
  monitor::CommandFilter filter_;
  monitor::CaptureIndicators indicators_;
  PortCounters counters_{};                                          // of the ports without a line name
  std::map<std::string, PortCounters, std::less<>> line_counters_;   // by line name, with several lines
  std::optional<std::chrono::system_clock::time_point> last_frame_sent_;
  std::uint64_t frames_sent_ = 0;
  std::uint8_t next_ix_ = 0;
  RecentTransactions recent_;
  std::unique_ptr<MonitorWriter> writer_;
  std::uint64_t dropped_before_ = 0;  // by writers replaced on reloads
  std::uint64_t written_before_ = 0;
};

}  // namespace unima::monitor
