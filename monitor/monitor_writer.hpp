#pragma once
// The monitor's writer: a bounded queue between the ports and the log (SPEC §5).
//
// Why a thread: writing the log can block on the disk (a full page cache, a slow SD card,
// a rotation's renames) and the event loop must never wait for that, so a dedicated
// writer thread formats and writes the lines. The event loop only copies the transaction
// into a free slot of a ring and publishes it with one atomic store (one producer, one
// consumer: no lock on the serving path); it takes the mutex only to wake a writer that
// sleeps. When the ring is full the transaction is dropped and counted, the log says how
// many were lost, and serving goes on. That is the seed's rule too (seed 004 §8: a missing
// monitor line never delays the right answer).
//
// spdlog 1.10's async logger was considered: its overflow policies either block the
// caller or overrun the oldest message, and it formats on the caller's thread; this queue
// drops the newest without blocking, counts exactly, and formats on the writer thread.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <type_traits>
#include <vector>

#include "monitor/monitor_line.hpp"
#include "modbus/transaction.hpp"

namespace unima::monitor {

/// Where monitor lines go; called on the writer thread only, with whole lines.
class MonitorSink {
 public:
  virtual ~MonitorSink() = default;
  virtual void write(std::string_view lines) = 0;
  /// The writer has nothing more for now: lines a sink held back must reach readers.
  virtual void flush() {}
};

class MonitorWriter {
 public:
  struct Options {
    monitor::MonitorFormat format = monitor::MonitorFormat::text;
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
  /// Never waits for the writer. One thread pushes (the event loop; another one only
  /// after the first stopped pushing).
  bool push(const modbus::Transaction& transaction, std::uint8_t ix);

  std::uint64_t dropped() const { return dropped_total_.load(std::memory_order_relaxed); }
  std::uint64_t written() const { return written_total_.load(std::memory_order_relaxed); }
  std::size_t capacity() const { return capacity_; }

  /// Frames longer than this are logged cut (Rc still says their size): the largest TCP
  /// ADU; RTU's is 256.
  static constexpr std::size_t max_frame = 260;

 private:
  static constexpr std::size_t cache_line = 64;  // x86-64's and most ARM cores'
  // One transaction as copied from the port, so the port may reuse its buffers at once.
  // Trivial to construct: the ring is allocated untouched, and a slot costs memory only
  // once a transaction was copied into it. The response follows the query in `frames`,
  // so a transaction fills a few adjacent cache lines, not a 600-byte stride; each slot
  // begins a cache line, so that prepare_slot knows which lines the next one takes.
  struct alignas(cache_line) Entry {
    std::chrono::system_clock::rep time;  // ticks since the epoch (a time_point would zero itself)
    std::uint32_t rc;  // the query's size on the wire, even when longer than kept
    std::uint16_t query_size;
    std::uint16_t response_size;
    modbus::PortKind port;
    modbus::TransactionState state;
    std::uint8_t ix;
    std::uint8_t peer_size;
    std::uint8_t line_size;
    char peer[64];  // "address:port" of a TCP client; longer is cut
    char line[16];  // the line's name when there are several (config: at most 16 characters)
    std::uint8_t frames[2 * max_frame];  // the query, then the response

    // How far into the slot this transaction reaches.
    std::size_t extent() const { return offsetof(Entry, frames) + query_size + response_size; }
  };
  enum class WriterState : std::uint8_t { idle, batching, busy };

  void run();
  static void prepare_slot(const Entry& slot, std::size_t extent);
  void wait_for_work(std::uint64_t head);
  // The last port name formatted, built again only when the port or the peer changes: a
  // client's transactions come in runs.
  struct PortName {
    modbus::PortKind port{};
    std::string peer;
    std::string line;
    std::string name;
  };
  // Writes the entry's line at `out`, which has room for max_line bytes; returns its end.
  char* format(const Entry& entry, char* out, PortName& port) const;
  static const std::size_t max_line;
  // The next slot after `index`: counting on is cheaper than dividing a position.
  std::size_t next_slot(std::size_t index) const { return index + 1 == capacity_ ? 0 : index + 1; }
  static_assert(std::is_trivially_default_constructible_v<Entry>);

  std::vector<std::unique_ptr<MonitorSink>> sinks_;
  Options options_;
  std::size_t capacity_;
  std::unique_ptr<Entry[]> slots_;

  // Positions count every transaction ever queued; [head, tail) are queued. The pusher
  // alone moves tail, the writer alone moves head, each on its own cache line.
  alignas(cache_line) std::atomic<std::uint64_t> tail_{0};
  std::size_t tail_slot_ = 0;  // the pusher's: the slot of tail
  alignas(cache_line) std::atomic<std::uint64_t> head_{0};
  std::atomic<WriterState> writer_state_{WriterState::busy};
  std::atomic<bool> stopping_{false};
  std::uint64_t dropped_reported_ = 0;  // the writer's: drops the log already told

  std::mutex mutex_;  // only for sleeping and waking the writer
  std::condition_variable wake_;

  std::atomic<std::uint64_t> dropped_total_{0};
  std::atomic<std::uint64_t> written_total_{0};
  std::thread thread_;
};

}  // namespace unima::monitor
