#include "daemon/monitor_writer.hpp"

#include <algorithm>
#include <cassert>
#include <cstring>  // memrchr (GNU) too
#include <utility>

namespace unima::daemon {

namespace {
constexpr std::size_t write_slice = 128 * 1024;
constexpr std::size_t max_peer = 64;  // "address:port" of a TCP client; longer is cut

// monitor_line_bound() of the longest line push writes: "tcp:" and the longest peer kept,
// and every byte of both frames kept.
constexpr std::size_t max_line = 256 + 6 * (4 + max_peer) + 3 * (2 * MonitorWriter::max_frame) + 2;

std::span<const std::uint8_t> kept(std::span<const std::uint8_t> frame) {
  return frame.first(std::min(frame.size(), MonitorWriter::max_frame));
}
}  // namespace

MonitorWriter::MonitorWriter(std::vector<std::unique_ptr<MonitorSink>> sinks, Options options)
    : sinks_(std::move(sinks)), options_(options), capacity_(std::max<std::size_t>(options.capacity, 1)),
      // Room for the longest line even when the end of the ring had to be skipped.
      ring_size_(std::max(capacity_ * bytes_per_transaction, 2 * max_line)),
      ring_(std::make_unique_for_overwrite<char[]>(ring_size_)) {
  assert(ring_size_ < (std::size_t{1} << 31));  // positions count bytes modulo 2^32
  thread_ = std::thread([this] { run(); });
}

MonitorWriter::~MonitorWriter() { stop(); }

void MonitorWriter::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_.store(true);
  }
  wake_.notify_one();
  if (thread_.joinable()) thread_.join();
}

bool MonitorWriter::push(const modbus::Transaction& t, std::uint8_t ix) {
  const auto tail = unpack(tail_.load(std::memory_order_relaxed));
  const auto head = unpack(head_.load(std::memory_order_acquire));
  const auto drop = [&] {
    dropped_total_.fetch_add(1, std::memory_order_relaxed);
    return false;
  };
  if (tail.lines - head.lines == capacity_ || stopping_.load(std::memory_order_relaxed)) return drop();

  // A client's transactions come in runs: its port name is built once per run.
  const auto peer = t.peer.substr(0, max_peer);
  if (port_name_.empty() || t.port != named_port_ || peer != named_peer_) {
    named_port_ = t.port;
    named_peer_.assign(peer);
    port_name_.clear();
    modbus::append_port_name(port_name_, t.port, peer);
  }
  const modbus::Transaction cut{t.port, t.peer, t.time, t.state, kept(t.query), kept(t.response)};
  auto fields = modbus::monitor_fields(cut, ix, port_name_);
  fields.rc = t.query.size();
  const auto bound = modbus::monitor_line_bound(fields);
  assert(bound <= max_line);

  const std::size_t skip = tail_offset_ + bound > ring_size_ ? ring_size_ - tail_offset_ : 0;
  const std::uint32_t queued_bytes = tail.bytes - head.bytes;
  if (queued_bytes + skip + bound > ring_size_) return drop();
  if (skip > 0) {
    lap_end_.store(tail_offset_, std::memory_order_relaxed);
    tail_offset_ = 0;
  }
  char* const line = ring_.get() + tail_offset_;
  const auto size = static_cast<std::size_t>(modbus::write_monitor_line(line, fields, options_.format) - line);
  tail_offset_ += size;
  if (tail_offset_ == ring_size_) {
    lap_end_.store(ring_size_, std::memory_order_relaxed);
    tail_offset_ = 0;
  }
  // A release store, not a fence: a fence would wait here for the line's cache misses.
  // Its price is that this push may miss a writer falling asleep at the same moment;
  // the writer covers that by looking once more after a short wait (wait_for_work).
  tail_.store(pack({tail.lines + 1, static_cast<std::uint32_t>(tail.bytes + skip + size)}),
              std::memory_order_release);
  const auto state = writer_state_.load(std::memory_order_relaxed);
  // Only a sleeping writer needs the (system-call) wake-up; a batching one is cut short
  // when the queue is half full.
  const bool wake = state == WriterState::idle ||
                    (state == WriterState::batching &&
                     tail.lines + 1 - unpack(head_.load(std::memory_order_relaxed)).lines >= capacity_ / 2);
  if (wake) {
    { std::lock_guard lock(mutex_); }  // the writer is either before its check or waiting
    wake_.notify_one();
  }
  return true;
}

// Sleeps until a transaction is queued, then gives the port the batch window to queue
// more, so that a busy port costs one wake-up and one write per batch. A push that raced
// with the writer falling asleep may not have woken it (see push), so the first wait is
// a timed one: only after a quiet batch window does the writer sleep until woken, which
// costs an idle daemon one wake-up after its last transaction, not one per period.
void MonitorWriter::wait_for_work(std::uint32_t head_lines) {
  const auto queued_lines = [&] { return unpack(tail_.load(std::memory_order_acquire)).lines - head_lines; };
  const auto queued = [&] { return queued_lines() != 0 || stopping_.load(); };
  std::unique_lock lock(mutex_);
  writer_state_.store(WriterState::idle, std::memory_order_seq_cst);
  const auto window = options_.batch_window.count() > 0 ? options_.batch_window : std::chrono::milliseconds(10);
  if (!wake_.wait_for(lock, window, queued)) {
    // Quiet: what the sinks hold back goes out now. Unlocked, so that a push meanwhile
    // never waits for the disk; it finds the writer idle and wakes it as usual.
    lock.unlock();
    for (const auto& sink : sinks_) sink->flush();
    lock.lock();
    wake_.wait(lock, queued);
  }
  if (!stopping_.load() && options_.batch_window.count() > 0) {
    writer_state_.store(WriterState::batching, std::memory_order_relaxed);
    wake_.wait_for(lock, options_.batch_window, [&] { return stopping_.load() || queued_lines() >= capacity_ / 2; });
  }
  writer_state_.store(WriterState::busy, std::memory_order_relaxed);
}

void MonitorWriter::write_out(std::size_t from, std::size_t to, Position& head) {
  // Slices keep the room coming back to the pusher while a big batch is being written.
  while (from != to) {
    std::size_t end = to;
    if (to - from > write_slice) {
      const auto* last = static_cast<const char*>(::memrchr(ring_.get() + from, '\n', write_slice));
      assert(last != nullptr);  // lines are far shorter than a slice
      end = static_cast<std::size_t>(last - ring_.get()) + 1;
    }
    for (const auto& sink : sinks_) sink->write({ring_.get() + from, end - from});
    head.bytes += static_cast<std::uint32_t>(end - from);
    give_back(head);  // still the lines before the batch: the pusher counts too few free, never too many
    from = end;
  }
}

void MonitorWriter::run() {
  std::string notice;
  while (true) {
    auto head = unpack(head_.load(std::memory_order_relaxed));
    wait_for_work(head.lines);
    // The bytes [head, tail) are the writer's until head moves: push only fills free ones.
    const auto tail = unpack(tail_.load(std::memory_order_acquire));
    if (tail.lines == head.lines && stopping_.load()) break;
    const auto dropped = dropped_total_.load(std::memory_order_relaxed) - dropped_reported_;
    dropped_reported_ += dropped;

    const std::size_t queued_bytes = tail.bytes - head.bytes;
    if (head_offset_ + queued_bytes <= ring_size_) {
      write_out(head_offset_, head_offset_ + queued_bytes, head);
      head_offset_ = (head_offset_ + queued_bytes) % ring_size_;
    } else {  // the lines wrap: to the lap's end, past the skipped room, then from the start
      const auto lap_end = lap_end_.load(std::memory_order_relaxed);
      write_out(head_offset_, lap_end, head);
      head.bytes += static_cast<std::uint32_t>(ring_size_ - lap_end);
      head_offset_ = head_offset_ + queued_bytes - ring_size_;
      write_out(0, head_offset_, head);
    }
    if (dropped > 0) {
      notice.clear();
      modbus::append_drop_notice(notice, std::chrono::system_clock::now(), dropped, options_.format);
      for (const auto& sink : sinks_) sink->write(notice);
    }
    written_total_.fetch_add(tail.lines - head.lines, std::memory_order_relaxed);
    give_back(tail);
  }
}

}  // namespace unima::daemon
