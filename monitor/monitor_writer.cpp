#include "monitor/monitor_writer.hpp"

#include <algorithm>
#include <cassert>
#include <cstring>
#include <utility>

namespace unima::monitor {

namespace {
constexpr std::size_t write_slice = 128 * 1024;
}  // namespace

// monitor_line_bound() of the longest transaction an Entry holds: "tcp:" and the peer,
// and every byte of both frames.
constexpr std::size_t MonitorWriter::max_line =
    256 + 6 * (4 + sizeof(Entry::peer) + 1 + sizeof(Entry::line)) + 3 * sizeof(Entry::frames) + 2;

MonitorWriter::MonitorWriter(std::vector<std::unique_ptr<MonitorSink>> sinks, Options options)
    : sinks_(std::move(sinks)), options_(options), capacity_(std::max<std::size_t>(options.capacity, 1)),
      slots_(std::make_unique_for_overwrite<Entry[]>(capacity_)) {
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
  const auto tail = tail_.load(std::memory_order_relaxed);
  if (tail - head_.load(std::memory_order_acquire) == capacity_ || stopping_.load(std::memory_order_relaxed)) {
    dropped_total_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  Entry& e = slots_[tail_slot_];
  e.time = t.time.time_since_epoch().count();
  e.rc = static_cast<std::uint32_t>(t.query.size());
  e.query_size = static_cast<std::uint16_t>(std::min(t.query.size(), max_frame));
  e.response_size = static_cast<std::uint16_t>(std::min(t.response.size(), max_frame));
  e.port = t.port;
  e.state = t.state;
  e.ix = ix;
  e.peer_size = static_cast<std::uint8_t>(std::min(t.peer.size(), sizeof e.peer));
  // An empty span may have no data pointer, which memcpy must not get even for 0 bytes.
  if (e.peer_size > 0) std::memcpy(e.peer, t.peer.data(), e.peer_size);
  e.line_size = static_cast<std::uint8_t>(std::min(t.line.size(), sizeof e.line));
  if (e.line_size > 0) std::memcpy(e.line, t.line.data(), e.line_size);
  if (e.query_size > 0) std::memcpy(e.frames, t.query.data(), e.query_size);
  if (e.response_size > 0) std::memcpy(e.frames + e.query_size, t.response.data(), e.response_size);
  tail_slot_ = next_slot(tail_slot_);
  // A release store, not a fence: a fence would wait here for the slot's cache misses.
  // Its price is that this push may miss a writer falling asleep at the same moment;
  // the writer covers that by looking once more after a short wait (wait_for_work).
  tail_.store(tail + 1, std::memory_order_release);
  prepare_slot(slots_[tail_slot_], e.extent());
  const auto state = writer_state_.load(std::memory_order_relaxed);
  // Only a sleeping writer needs the (system-call) wake-up; a batching one is cut short
  // when the queue is half full.
  const bool wake = state == WriterState::idle ||
                    (state == WriterState::batching &&
                     tail + 1 - head_.load(std::memory_order_relaxed) >= capacity_ / 2);
  if (wake) {
    { std::lock_guard lock(mutex_); }  // the writer is either before its check or waiting
    wake_.notify_one();
  }
  return true;
}

// The writer read the next slot's lines when it was last used, so the other core holds
// them (or they left this one's caches): storing into them waits for the lines, and the
// loop's next locked instruction — each system call's cancellation bookkeeping, a
// shared_ptr's count — waits for those stores to land: 150 – 200 ns a request at 8
// connections, measured (docs/performance.md, "What the daemon does for speed"). Asking for the lines now, a
// transaction ahead, takes that wait off the serving path; the next transaction is most
// likely as long as this one.
void MonitorWriter::prepare_slot(const Entry& slot, std::size_t extent) {
  const auto* const begin = reinterpret_cast<const char*>(&slot);
  for (std::size_t line = 0; line < extent; line += cache_line) __builtin_prefetch(begin + line, 1);
}

// Sleeps until a transaction is queued, then gives the port the batch window to queue
// more, so that a busy port costs one wake-up and one write per batch. A push that raced
// with the writer falling asleep may not have woken it (see push), so the first wait is
// a timed one: only after a quiet batch window does the writer sleep until woken, which
// costs an idle daemon one wake-up after its last transaction, not one per period.
void MonitorWriter::wait_for_work(std::uint64_t head) {
  const auto queued = [&] { return tail_.load(std::memory_order_acquire) != head || stopping_.load(); };
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
    wake_.wait_for(lock, options_.batch_window, [&] {
      return stopping_.load() || tail_.load(std::memory_order_acquire) - head >= capacity_ / 2;
    });
  }
  writer_state_.store(WriterState::busy, std::memory_order_relaxed);
}

char* MonitorWriter::format(const Entry& e, char* out, PortName& port) const {
  const modbus::Transaction t{e.port,
                              std::string_view(e.peer, e.peer_size),
                              std::chrono::system_clock::time_point(std::chrono::system_clock::duration(e.time)),
                              e.state,
                              std::span<const std::uint8_t>(e.frames, e.query_size),
                              std::span<const std::uint8_t>(e.frames + e.query_size, e.response_size),
                              false,
                              std::string_view(e.line, e.line_size)};
  const auto line = t.line;
  if (port.name.empty() || port.port != t.port || port.peer != t.peer || port.line != line) {
    port.port = t.port;
    port.peer.assign(t.peer);
    port.line.assign(line);
    port.name.clear();
    monitor::append_port_name(port.name, t.port, t.peer, line);
  }
  auto fields = monitor::monitor_fields(t, e.ix, port.name);
  fields.rc = e.rc;
  assert(monitor::monitor_line_bound(fields) <= max_line);
  return monitor::write_monitor_line(out, fields, options_.format);
}

void MonitorWriter::run() {
  // Lines are formatted straight into this buffer (no string to grow or clear) and go to
  // the sinks whenever a slice is full: a batch of a busy port is megabytes of text, and
  // slices keep the daemon's memory small at the price of a few more writes.
  const auto text = std::make_unique_for_overwrite<char[]>(write_slice + max_line);
  std::size_t used = 0;
  const auto write_out = [&] {
    if (used == 0) return;
    for (const auto& sink : sinks_) sink->write({text.get(), used});
    used = 0;
  };
  PortName port;
  std::string notice;
  std::size_t head_slot = 0;
  while (true) {
    const auto head = head_.load(std::memory_order_relaxed);
    wait_for_work(head);
    // The slots [head, tail) are the writer's until head moves: push only fills free ones.
    const auto tail = tail_.load(std::memory_order_acquire);
    if (tail == head && stopping_.load()) break;
    const auto dropped = dropped_total_.load(std::memory_order_relaxed) - dropped_reported_;
    dropped_reported_ += dropped;

    for (auto position = head; position != tail; ++position, head_slot = next_slot(head_slot)) {
      used = static_cast<std::size_t>(format(slots_[head_slot], text.get() + used, port) - text.get());
      if (used >= write_slice) write_out();
    }
    if (dropped > 0) {
      notice.clear();
      monitor::append_drop_notice(notice, std::chrono::system_clock::now(), dropped, options_.format);
      std::memcpy(text.get() + used, notice.data(), notice.size());  // shorter than max_line
      used += notice.size();
    }
    write_out();
    written_total_.fetch_add(tail - head, std::memory_order_relaxed);
    head_.store(tail, std::memory_order_release);
  }
}

}  // namespace unima::monitor
