#pragma once
// The monitor's writer: a bounded queue between the ports and the log (SPEC §5).
//
// Why a thread: writing the log can block on the disk (a full page cache, a slow SD card,
// a rotation's renames, a direct write waiting for the disk) and the event loop must never
// wait for that, so a dedicated writer thread hands the lines to the sinks. The event loop
// formats each line straight into a free stretch of a byte ring and publishes it with one
// atomic store (one producer, one consumer: no lock on the serving path); it takes the
// mutex only to wake a writer that sleeps. When the ring is full the transaction is
// dropped and counted, the log says how many were lost, and serving goes on. That is the
// seed's rule too (seed 004 §8: a missing monitor line never delays the right answer).
//
// Why the loop formats rather than the writer: on a machine whose CPUs are all busy
// serving and being served, every moment the writer runs it displaces the loop or its
// clients, and at depth 1 the other one then waits too, so the writer's time costs about
// twice its length. Formatting on the loop costs the loop the formatting (~0.1 µs for a
// 64-register read) and leaves the writer little more than copying text to the disk
// (docs/performance.md, "Fourth pass").
//
// spdlog 1.10's async logger was considered: its overflow policies either block the
// caller or overrun the oldest message; this queue drops the newest without blocking and
// counts exactly.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
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
  /// The writer has nothing more for now: lines a sink held back must reach readers.
  virtual void flush() {}
};

class MonitorWriter {
 public:
  struct Options {
    modbus::MonitorFormat format = modbus::MonitorFormat::text;
    // Transactions; the ring also holds at most capacity * bytes_per_transaction bytes of
    // lines (a 64-register read's text line is 544 bytes), so longer lines fit fewer.
    std::size_t capacity = 4096;
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

  /// Formats the transaction's line into the queue; false (and counted) when the queue is
  /// full. Never waits for the writer. One thread pushes (the event loop; another one only
  /// after the first stopped pushing).
  bool push(const modbus::Transaction& transaction, std::uint8_t ix);

  std::uint64_t dropped() const { return dropped_total_.load(std::memory_order_relaxed); }
  std::uint64_t written() const { return written_total_.load(std::memory_order_relaxed); }
  std::size_t capacity() const { return capacity_; }

 static constexpr std::size_t bytes_per_transaction = 640;
  /// Frames longer than this are logged cut (Rc still says their size): the largest TCP
  /// ADU; RTU's is 256.
  static constexpr std::size_t max_frame = 260;

 private:
  // A queue position: the lines and the bytes (padding included) ever queued, both modulo
  // 2^32, in one word so that the writer reads a consistent pair with one load.
  struct Position {
    std::uint32_t lines;
    std::uint32_t bytes;
  };
  static std::uint64_t pack(Position p) { return std::uint64_t{p.lines} << 32 | p.bytes; }
  static Position unpack(std::uint64_t word) {
    return {static_cast<std::uint32_t>(word >> 32), static_cast<std::uint32_t>(word)};
  }
  enum class WriterState : std::uint8_t { idle, batching, busy };

  void run();
  void wait_for_work(std::uint32_t head_lines);
  // Hands the bytes [from, to) of the ring to the sinks in slices of whole lines, and
  // gives each slice's room back to the pusher once written.
  void write_out(std::size_t from, std::size_t to, Position& head);
  void give_back(Position head) { head_.store(pack(head), std::memory_order_release); }

  std::vector<std::unique_ptr<MonitorSink>> sinks_;
  Options options_;
  std::size_t capacity_;
  std::size_t ring_size_;
  std::unique_ptr<char[]> ring_;

  // [head, tail) is queued. The pusher alone moves tail, the writer alone moves head,
  // each on its own cache line. A line never wraps: when the room left at the end of the
  // ring might be too small, the pusher skips it (counted in bytes) and says where the
  // lines of that lap ended (lap_end_, published with tail).
  alignas(64) std::atomic<std::uint64_t> tail_{0};
  std::size_t tail_offset_ = 0;  // the pusher's: where in the ring tail is
  std::string port_name_;        // the pusher's: the last transaction's port name,
  modbus::PortKind named_port_{};  // for this port
  std::string named_peer_;         // and this peer
  std::atomic<std::size_t> lap_end_{0};
  alignas(64) std::atomic<std::uint64_t> head_{0};
  std::size_t head_offset_ = 0;  // the writer's
  std::atomic<WriterState> writer_state_{WriterState::busy};
  std::atomic<bool> stopping_{false};
  std::uint64_t dropped_reported_ = 0;  // the writer's: drops the log already told

  std::mutex mutex_;  // only for sleeping and waking the writer
  std::condition_variable wake_;

  std::atomic<std::uint64_t> dropped_total_{0};
  std::atomic<std::uint64_t> written_total_{0};
  std::thread thread_;
};

}  // namespace unima::daemon
