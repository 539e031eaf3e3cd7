#include "io/mqtt/history_buffer.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <deque>
#include <system_error>
#include <utility>

#include <spdlog/spdlog.h>

#include "io/durable_file.hpp"
#include "platform/journal_thread.hpp"

namespace unima::io {
namespace {

using namespace std::chrono_literals;
using mqtt::history_header;
using mqtt::HistoryEntry;
using mqtt::HistoryPlace;
using mqtt::LoadedHistory;

constexpr auto sync_interval = 1s;

std::string read_range(int fd, std::uint64_t offset, std::uint64_t size) {
  std::string bytes(size, '\0');
  std::uint64_t done = 0;
  while (done < size) {
    const auto n = ::pread(fd, bytes.data() + done, size - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw std::system_error(errno, std::generic_category(), "read");
    if (n == 0) throw std::runtime_error("read: the file is shorter than its entries");
    done += static_cast<std::uint64_t>(n);
  }
  return bytes;
}

// Copied in pieces: a full buffer is max_size bytes, which never sit in memory at once.
void copy_range(int from, int to, std::uint64_t offset, std::uint64_t end) {
  constexpr std::uint64_t piece = 256 * 1024;
  for (auto at = offset; at < end; at += piece) write_all(to, read_range(from, at, std::min(piece, end - at)));
}

struct Loaded {
  Descriptor fd;
  std::uint64_t size = 0;
  LoadedHistory history;
};

Loaded load(const std::filesystem::path& path) {
  Loaded loaded;
  const auto begin_empty = [&] {
    loaded.fd = replace_file(path, history_header);
    loaded.size = history_header.size();
    loaded.history = {};
  };
  const auto bytes = read_if_present(path);
  if (!bytes) {
    begin_empty();
    return loaded;
  }
  loaded.history = mqtt::parse_history(*bytes);
  switch (loaded.history.status) {
    case LoadedHistory::Status::ok:
    case LoadedHistory::Status::torn_tail:
      if (loaded.history.good_bytes < history_header.size()) {
        begin_empty();
        break;
      }
      if (loaded.history.status == LoadedHistory::Status::torn_tail)
        spdlog::info("mqtt: history buffer {} {}: the line a crash cut short is dropped", path.string(), loaded.history.problem);
      loaded.fd = Descriptor(::open(path.c_str(), O_RDWR | O_APPEND | O_NOFOLLOW | O_CLOEXEC));
      if (loaded.fd.get() < 0) throw std::system_error(errno, std::generic_category(), "cannot open it");
      if (::ftruncate(loaded.fd.get(), static_cast<off_t>(loaded.history.good_bytes)) != 0)
        throw std::system_error(errno, std::generic_category(), "cannot drop its torn end");
      loaded.size = loaded.history.good_bytes;
      break;
    case LoadedHistory::Status::damaged:
    case LoadedHistory::Status::foreign: {
      // As the state file (SPEC §10): kept for a human, never read again nor overwritten.
      const auto aside = set_aside(path);
      spdlog::error("mqtt: history buffer {} {}: kept aside as {}; a new one is begun", path.string(), loaded.history.problem,
                    aside.string());
      begin_empty();
      break;
    }
  }
  return loaded;
}

}  // namespace

// Two threads share the buffer (io/journal_thread; a rewrite of a full buffer copies
// max_size bytes, longer still than a sync). The loop hands entries, read requests and
// acknowledgements over; it never waits for the disk. The thread's turn comes once a
// second: it appends everything handed over since in one write, marks what was
// acknowledged, and fdatasyncs — one sync per second however many entries came, and none
// when nothing did. A read request is urgent (history is sent as fast as the broker
// acknowledges it): its turn writes what was handed over, without a sync, and reads the
// entries back from the file. What the loop sees of the thread's work comes back as posts
// to the loop, or in the atomic counters.
struct HistoryBuffer::Shared {
  Shared(asio::io_context& io, std::filesystem::path path, std::uint64_t max_size, Loaded loaded)
      : io(io), path(std::move(path)), max_size(max_size), fd(std::move(loaded.fd)), size(loaded.size),
        pending(loaded.history.pending.begin(), loaded.history.pending.end()), last_sequence(loaded.history.last_sequence) {
    for (const auto& place : pending) pending_bytes += place.size;
    publish_counters();
  }

  asio::io_context& io;
  const std::filesystem::path path;
  const std::uint64_t max_size;

  // Under the thread's lock.
  struct Request {
    std::uint64_t after;
    std::size_t count;
    Entries done;
  };
  std::vector<std::pair<std::string, std::string>> queued;  // bank, document
  std::vector<Request> requests;
  std::uint64_t acknowledged = 0;

  // Counters, written by the thread.
  std::atomic<std::uint64_t> bytes{0}, messages{0}, dropped{0}, syncs{0}, failures{0};

  // The thread's side.
  Descriptor fd;
  std::uint64_t size;                // of the file
  std::deque<HistoryPlace> pending;  // written, not acknowledged, oldest first
  std::uint64_t pending_bytes = 0;
  std::uint64_t last_sequence;
  std::uint64_t marked = 0;  // the last acknowledgement written
  bool dirty = false;        // written since the last sync
  bool drop_logged = false;  // once per filling: until the buffer empties again
  bool failure_logged = false;
  std::vector<std::pair<std::string, std::string>> batch;  // swapped with `queued`
  std::vector<Request> reading;                            // swapped with `requests`
  std::chrono::steady_clock::time_point next_sync;
  platform::JournalThread thread;

  /// One turn of the thread (`last`: the stop's); when the next is due.
  std::chrono::steady_clock::time_point turn(bool last, const std::weak_ptr<Shared>& self);
  void write_queued(std::vector<std::pair<std::string, std::string>>& batch);
  void mark(std::uint64_t sequence);
  void append(const std::string& records, std::vector<HistoryPlace> added);
  void rewrite(const std::string& records, std::vector<HistoryPlace> added);
  void sync();
  void serve(Request& request, const std::weak_ptr<Shared>& self);
  void failed(const std::string& what, std::size_t lost);
  void publish_counters() {
    bytes = pending_bytes;
    messages = pending.size();
  }
};

void HistoryBuffer::Shared::failed(const std::string& what, std::size_t lost) {
  failures += 1;
  dropped += lost;
  if (!std::exchange(failure_logged, true))
    spdlog::error("mqtt: history buffer {}: {}; the history of this outage is incomplete (logged once)", path.string(), what);
}

void HistoryBuffer::Shared::write_queued(std::vector<std::pair<std::string, std::string>>& batch) {
  if (batch.empty()) return;
  std::string records;
  std::vector<HistoryPlace> added;
  for (auto& [bank, document] : batch) {
    const auto line = mqtt::encode_history_entry({++last_sequence, std::move(bank), std::move(document)});
    added.push_back({last_sequence, records.size(), line.size()});  // offsets within `records` for now
    records += line;
  }
  batch.clear();
  append(records, std::move(added));
}

void HistoryBuffer::Shared::mark(std::uint64_t sequence) {
  if (sequence <= marked) return;
  marked = sequence;
  while (!pending.empty() && pending.front().sequence <= sequence) {
    pending_bytes -= pending.front().size;
    pending.pop_front();
  }
  append(mqtt::encode_history_acknowledged(sequence), {});
}

void HistoryBuffer::Shared::append(const std::string& records, std::vector<HistoryPlace> added) {
  if (size + records.size() > max_size) return rewrite(records, std::move(added));
  try {
    write_all(fd.get(), records);
  } catch (const std::system_error& e) {
    (void)!::ftruncate(fd.get(), static_cast<off_t>(size));  // best effort: a part of a line would be a torn tail
    return failed(e.what(), added.size());
  }
  for (auto& place : added) {
    place.offset += size;
    pending_bytes += place.size;
    pending.push_back(place);
  }
  size += records.size();
  dirty = true;
  failure_logged = false;
}

// Full: the file becomes the header, the entries kept — a part of the old file's end, copied
// as it is — and the new ones, by atomic replace; what was acknowledged goes with it.
void HistoryBuffer::Shared::rewrite(const std::string& records, std::vector<HistoryPlace> added) {
  std::vector<std::uint64_t> sizes;
  for (const auto& place : pending) sizes.push_back(place.size);
  for (const auto& place : added) sizes.push_back(place.size);
  const auto drop = mqtt::oldest_to_drop(sizes, max_size - history_header.size());
  const auto drop_pending = std::min(drop, pending.size());
  const auto drop_added = drop - drop_pending;
  const auto copy_from = drop_pending < pending.size() ? pending[drop_pending].offset : size;
  const auto new_from = drop_added < added.size() ? added[drop_added].offset : records.size();
  const auto copied = size - copy_from;
  try {
    auto next = replace_file(path, [&](int out) {
      write_all(out, history_header);
      copy_range(fd.get(), out, copy_from, size);
      write_all(out, std::string_view(records).substr(new_from));
    });
    fd = std::move(next);
  } catch (const std::system_error& e) {
    return failed(e.what(), added.size());
  }
  ++syncs;
  dirty = false;
  failure_logged = false;
  if (drop > 0) {
    dropped += drop;
    if (!std::exchange(drop_logged, true))
      spdlog::warn("mqtt: history buffer {} is full ({} bytes): the oldest history is dropped and counted "
                   "(unima_bridge_mqtt_buffer_dropped_total; logged once until it empties)",
                   path.string(), max_size);
  }
  for (std::size_t i = 0; i < drop_pending; ++i) pending_bytes -= pending[i].size;
  pending.erase(pending.begin(), pending.begin() + static_cast<std::ptrdiff_t>(drop_pending));
  for (auto& place : pending) place.offset = place.offset - copy_from + history_header.size();
  for (std::size_t i = drop_added; i < added.size(); ++i) {
    auto place = added[i];
    place.offset = history_header.size() + copied + (place.offset - new_from);
    pending_bytes += place.size;
    pending.push_back(place);
  }
  size = history_header.size() + copied + (records.size() - new_from);
}

void HistoryBuffer::Shared::sync() {
  // Everything delivered: the file begins again from its header (it would otherwise hold
  // the delivered history until the next time it is full).
  if (pending.empty() && size > history_header.size()) {
    try {
      fd = replace_file(path, history_header);
      size = history_header.size();
      ++syncs;
      dirty = false;
      drop_logged = false;
    } catch (const std::system_error& e) {
      failed(e.what(), 0);
    }
  }
  if (!dirty) return;
  try {
    sync_data(fd.get());
    ++syncs;
    dirty = false;
  } catch (const std::system_error& e) {
    failed(e.what(), 0);
  }
}

void HistoryBuffer::Shared::serve(Request& request, const std::weak_ptr<Shared>& self) {
  std::vector<HistoryEntry> entries;
  const auto first = std::partition_point(pending.begin(), pending.end(),
                                          [&](const HistoryPlace& place) { return place.sequence <= request.after; });
  const auto count = std::min<std::size_t>(request.count, static_cast<std::size_t>(pending.end() - first));
  if (count > 0) {
    const auto& last = first[static_cast<std::ptrdiff_t>(count - 1)];
    try {
      const auto span = read_range(fd.get(), first->offset, last.offset + last.size - first->offset);
      for (auto place = first; place != first + static_cast<std::ptrdiff_t>(count); ++place) {
        auto entry = mqtt::parse_history_entry(std::string_view(span).substr(place->offset - first->offset, place->size));
        // Damaged on the disk since it was written: that entry alone is lost.
        if (entry && entry->sequence == place->sequence) entries.push_back(std::move(*entry));
        else failed("entry " + std::to_string(place->sequence) + " is damaged on the disk", 1);
      }
    } catch (const std::exception& e) {
      failed(e.what(), 0);
    }
  }
  asio::post(io, [self, done = std::move(request.done), entries = std::move(entries)]() mutable {
    if (self.lock()) done(std::move(entries));
  });
}

// The last turn writes and syncs what was handed over before the destructor.
std::chrono::steady_clock::time_point HistoryBuffer::Shared::turn(bool last, const std::weak_ptr<Shared>& self) {
  std::uint64_t acknowledge = 0;
  thread.take([&] {
    batch.swap(queued);
    reading.swap(requests);
    acknowledge = acknowledged;
  });
  write_queued(batch);
  mark(acknowledge);
  const auto now = std::chrono::steady_clock::now();
  if (now >= next_sync || last) {
    sync();
    next_sync = now + sync_interval;
  }
  for (auto& request : reading) serve(request, self);
  reading.clear();
  publish_counters();
  return next_sync;
}

HistoryBuffer::HistoryBuffer(asio::io_context& io, std::filesystem::path path, std::uint64_t max_size) : path_(std::move(path)) {
  try {
    auto loaded = load(path_);
    const auto& history = loaded.history;
    delivered_at_start_ = history.pending.empty() ? history.last_sequence : history.pending.front().sequence - 1;
    shared_ = std::make_shared<Shared>(io, path_, max_size, std::move(loaded));
  } catch (const std::exception& e) {
    throw std::runtime_error("mqtt.buffer.file " + path_.string() + ": " + e.what());
  }
  shared_->next_sync = std::chrono::steady_clock::now() + sync_interval;
  shared_->thread.start(
      [shared = shared_.get(), weak = std::weak_ptr<Shared>(shared_)](bool last) {
        return std::optional(shared->turn(last, weak));
      },
      shared_->next_sync);
  spdlog::info("mqtt: history buffer {} holds {} documents not yet sent", path_.string(), shared_->pending.size());
}

HistoryBuffer::~HistoryBuffer() { shared_->thread.stop(); }

void HistoryBuffer::append(std::string_view bank, std::string document) {
  shared_->thread.hand_over([&] { shared_->queued.emplace_back(std::string(bank), std::move(document)); }, false);
}

void HistoryBuffer::read(std::uint64_t after, std::size_t count, Entries done) {
  shared_->thread.hand_over([&] { shared_->requests.push_back({after, count, std::move(done)}); }, true);
}

void HistoryBuffer::acknowledge(std::uint64_t sequence) {
  shared_->thread.hand_over([&] { shared_->acknowledged = std::max(shared_->acknowledged, sequence); }, false);
}

HistoryBuffer::Counters HistoryBuffer::counters() const {
  const auto& s = *shared_;
  return {s.bytes, s.messages, s.dropped, s.syncs, s.failures};
}

}  // namespace unima::io
