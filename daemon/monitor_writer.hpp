#pragma once
// The monitor's writer: a bounded queue between the ports and the log (SPEC §5).
//
// Why a thread: writing the log can block on the disk (a full page cache, a slow SD card,
// a rotation's renames) and the event loop must never wait for that, so a dedicated
// writer thread formats and writes the lines. The ports only copy the transaction into a
// preallocated slot under a short mutex; when the queue is full the transaction is
// dropped and counted, the log says how many were lost, and serving goes on. That is the
// seed's rule too (seed 004 §8: a missing monitor line never delays the right answer).
//
// spdlog 1.10's async logger was considered: its overflow policies either block the
// caller or overrun the oldest message, and it formats on the caller's thread; this queue
// drops the newest without blocking, counts exactly, and formats on the writer thread.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string_view>
#include <thread>
#include <vector>

#include "modbus/monitor_line.hpp"
#include "modbus/transaction.hpp"

namespace unima::daemon {

/// Where monitor lines go; called on the writer thread only, with whole lines.
class MonitorSink {
 public:
  virtual ~MonitorSink() = default;
  virtual void write(std::string_view lines) = 0;
};

class MonitorWriter {
 public:
  struct Options {
    modbus::MonitorFormat format = modbus::MonitorFormat::text;
    std::size_t capacity = 4096;  // transactions
    // After the first transaction wakes it, the writer waits this long for more, so a
    // busy port costs one wake-up per batch, not one per transaction.
    std::chrono::milliseconds batch_window{10};
  };

  MonitorWriter(std::vector<std::unique_ptr<MonitorSink>> sinks, Options options);
  /// Writes what is still queued, then stops the thread.
  ~MonitorWriter();
  /// The same, earlier; pushes after it are dropped.
  void stop();
  MonitorWriter(const MonitorWriter&) = delete;
  MonitorWriter& operator=(const MonitorWriter&) = delete;

  /// Copies the transaction into the queue; false (and counted) when the queue is full.
  /// Never waits for the writer. Safe from any thread.
  bool push(const modbus::Transaction& transaction, std::uint8_t ix);

  std::uint64_t dropped() const { return dropped_total_.load(std::memory_order_relaxed); }
  std::uint64_t written() const { return written_total_.load(std::memory_order_relaxed); }
  std::size_t capacity() const { return slots_.size(); }

 private:
  // One transaction as copied from the port, so the port may reuse its buffers at once.
  struct Entry {
    static constexpr std::size_t max_frame = 260;  // the largest TCP ADU; RTU's is 256
    std::chrono::system_clock::time_point time;
    std::uint32_t rc = 0;  // the query's size on the wire, even when longer than kept
    std::uint16_t query_size = 0;
    std::uint16_t response_size = 0;
    modbus::PortKind port = modbus::PortKind::tcp;
    modbus::TransactionState state = modbus::TransactionState::done;
    std::uint8_t ix = 0;
    std::uint8_t peer_size = 0;
    char peer[64];
    std::uint8_t query[max_frame];
    std::uint8_t response[max_frame];
  };
  enum class WriterState : std::uint8_t { idle, batching, busy };

  void run();
  void format(const Entry& entry, std::string& out, std::string& port) const;

  std::vector<std::unique_ptr<MonitorSink>> sinks_;
  Options options_;
  std::vector<Entry> slots_;

  std::mutex mutex_;
  std::condition_variable wake_;
  std::size_t head_ = 0;   // oldest queued slot
  std::size_t count_ = 0;  // queued slots
  std::uint64_t dropped_pending_ = 0;  // not yet reported in the log
  WriterState writer_state_ = WriterState::busy;
  bool stopping_ = false;

  std::atomic<std::uint64_t> dropped_total_{0};
  std::atomic<std::uint64_t> written_total_{0};
  std::thread thread_;
};

}  // namespace unima::daemon
