#include "daemon/monitor_writer.hpp"

#include <algorithm>
#include <cstring>
#include <utility>

namespace unima::daemon {

MonitorWriter::MonitorWriter(std::vector<std::unique_ptr<MonitorSink>> sinks, Options options)
    : sinks_(std::move(sinks)), options_(options), slots_(std::max<std::size_t>(options.capacity, 1)) {
  thread_ = std::thread([this] { run(); });
}

MonitorWriter::~MonitorWriter() { stop(); }

void MonitorWriter::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_one();
  if (thread_.joinable()) thread_.join();
}

bool MonitorWriter::push(const modbus::Transaction& t, std::uint8_t ix) {
  std::unique_lock lock(mutex_);
  if (count_ == slots_.size() || stopping_) {
    ++dropped_pending_;
    dropped_total_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  Entry& e = slots_[(head_ + count_) % slots_.size()];
  e.time = t.time;
  e.rc = static_cast<std::uint32_t>(t.query.size());
  e.query_size = static_cast<std::uint16_t>(std::min(t.query.size(), Entry::max_frame));
  e.response_size = static_cast<std::uint16_t>(std::min(t.response.size(), Entry::max_frame));
  e.port = t.port;
  e.state = t.state;
  e.ix = ix;
  e.peer_size = static_cast<std::uint8_t>(std::min(t.peer.size(), sizeof e.peer));
  // An empty span may have no data pointer, which memcpy must not get even for 0 bytes.
  if (e.peer_size > 0) std::memcpy(e.peer, t.peer.data(), e.peer_size);
  if (e.query_size > 0) std::memcpy(e.query, t.query.data(), e.query_size);
  if (e.response_size > 0) std::memcpy(e.response, t.response.data(), e.response_size);
  ++count_;
  // Only a waiting writer needs the (system-call) wake-up; a batching one is cut short
  // when the queue is half full.
  const bool wake = writer_state_ == WriterState::idle ||
                    (writer_state_ == WriterState::batching && count_ >= slots_.size() / 2);
  lock.unlock();
  if (wake) wake_.notify_one();
  return true;
}

void MonitorWriter::format(const Entry& e, std::string& out, std::string& port) const {
  const modbus::Transaction t{e.port,
                              std::string_view(e.peer, e.peer_size),
                              e.time,
                              e.state,
                              std::span<const std::uint8_t>(e.query, e.query_size),
                              std::span<const std::uint8_t>(e.response, e.response_size)};
  port.clear();
  modbus::append_port_name(port, t.port, t.peer);
  auto fields = modbus::monitor_fields(t, e.ix, port);
  fields.rc = e.rc;
  modbus::append_monitor_line(out, fields, options_.format);
}

void MonitorWriter::run() {
  std::string out;
  std::string port;
  std::unique_lock lock(mutex_);
  while (true) {
    writer_state_ = WriterState::idle;
    wake_.wait(lock, [this] { return count_ > 0 || stopping_; });
    if (!stopping_ && options_.batch_window.count() > 0) {
      writer_state_ = WriterState::batching;
      wake_.wait_for(lock, options_.batch_window, [this] { return stopping_ || count_ >= slots_.size() / 2; });
    }
    writer_state_ = WriterState::busy;
    if (count_ == 0 && stopping_) break;
    // The slots [head, head + n) are the writer's until head moves: push only fills
    // free slots, so they are read without the lock.
    const std::size_t head = head_;
    const std::size_t n = count_;
    const auto dropped = std::exchange(dropped_pending_, 0);
    lock.unlock();

    out.clear();
    for (std::size_t i = 0; i < n; ++i) format(slots_[(head + i) % slots_.size()], out, port);
    if (dropped > 0) modbus::append_drop_notice(out, std::chrono::system_clock::now(), dropped, options_.format);
    for (const auto& sink : sinks_) sink->write(out);
    written_total_.fetch_add(n, std::memory_order_relaxed);

    lock.lock();
    head_ = (head_ + n) % slots_.size();
    count_ -= n;
  }
}

}  // namespace unima::daemon
