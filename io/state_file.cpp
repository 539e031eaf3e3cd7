#include "io/state_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <ctime>
#include <optional>
#include <system_error>
#include <utility>
#include <vector>

#include <spdlog/spdlog.h>

#include "io/durable_file.hpp"
#include "io/loop_turn.hpp"
#include "platform/journal_thread.hpp"
#include "monitor/write_outage.hpp"
#include "state/state_journal.hpp"

namespace unima::io {
namespace {

using state::LoadedJournal;
using state::PersistedValue;
using state::StateImage;

// A journal this long is rewritten as one record per value: at about 20 bytes a record,
// some 3,000 writes between two rewrites, each rewrite one more fdatasync and a rename.
constexpr std::size_t compact_at = 64 * 1024;

StateImage load(const std::filesystem::path& path) {
  const auto bytes = read_if_present(path);
  if (!bytes) {
    spdlog::info("state: {} is new; no value set yet", path.string());
    return {};
  }
  const auto loaded = state::parse_journal(*bytes);
  switch (loaded.status) {
    case LoadedJournal::Status::ok: break;
    case LoadedJournal::Status::torn_tail:
      spdlog::info("state: {} {}: the write a crash cut short was never acknowledged; dropped", path.string(),
                   loaded.problem);
      break;
    case LoadedJournal::Status::damaged:
    case LoadedJournal::Status::foreign: {
      // SPEC §10: nothing of it is trusted. What comes before a damaged record may be an
      // older value than the one last acknowledged, which drivers must never get again.
      const auto aside = set_aside(path);
      spdlog::error("state: {} {}: kept aside as {}; starting with no value set", path.string(), loaded.problem,
                    aside.string());
      return {};
    }
  }
  return loaded.image;
}

state::PersistedValue persisted(const banks::WrittenValue& written) {
  using Kind = PersistedValue::Kind;
  if (written.bank == banks::BankId::W) return {Kind::w, written.offset, written.value};
  if (written.bank == banks::BankId::X) return {Kind::x, written.offset, written.value};
  return {Kind::output, static_cast<std::uint16_t>(written.offset - banks::c_bank::user_analog_outputs + 1),
          written.value};
}

}  // namespace

// Two threads share the work of a write (io/journal_thread). The loop hands the write's
// records over as one (so they are always taken into one batch together), urgently: a lone
// write does not wait for the end of the loop's turn. A turn of the thread takes everything
// queued, appends it, fdatasyncs, and posts one completion to the loop; the next takes what
// was queued during that sync (group commit). The loop keeps the writes' values until
// their completion: committed when durable, dropped when refused.
struct StateFile::Shared {
  Shared(asio::io_context& io, std::filesystem::path path, StateImage image, Descriptor fd, std::size_t size)
      : io(io), path(std::move(path)), fd(std::move(fd)), size(size), image(std::move(image)) {}

  asio::io_context& io;
  const std::filesystem::path path;

  // The loop's side.
  struct KeptWrite {
    std::uint64_t sequence;
    std::vector<banks::WrittenValue> values;
  };
  std::uint64_t kept = 0;  // the number of the last write kept
  std::uint64_t durable = 0;
  std::deque<KeptWrite> uncommitted;                   // kept, neither durable nor refused yet, in order
  std::deque<std::pair<std::uint64_t, Done>> waiters;  // in order of their sequence
  // Batches synced (or refused) whose writes are not all committed and answered yet, in
  // the order they were written; `finishing` while a slice of them is posted.
  struct Synced {
    std::uint64_t sequence;
    std::string error;  // empty: durable
    bool begun = false;
  };
  std::deque<Synced> finished_batches;
  bool finishing = false;
  SliceSize slice{writes_per_slice};  // how many writes the next slice takes
  Outcome outcome;
  monitor::WriteOutage outage;
  Counters counters;

  // A record as the loop queues it: `continued` while more of its write follow. (A member
  // type, not a file-local one: Shared has external linkage.)
  struct QueuedRecord {
    PersistedValue value;
    bool continued = false;
  };

  // Under the thread's lock.
  std::vector<QueuedRecord> queued;  // kept, not yet taken by the thread
  std::uint64_t queued_up_to = 0;    // the number of the last write among them

  // The thread's side.
  Descriptor fd;
  std::size_t size;
  StateImage image;      // what the file holds, for a rewrite: never a refused write's values
  bool rewrite = false;  // after a failed append, whose bytes may be on the disk in part
  std::vector<QueuedRecord> batch;  // swapped with `queued`: both keep their capacity
  std::string records;
  platform::JournalThread thread;

  std::uint64_t queue(std::span<const banks::WrittenValue> write);
  void synced(std::uint64_t sequence, std::string error, const std::weak_ptr<Shared>& self);
  void finish_slice(const std::weak_ptr<Shared>& self);
  void turn(const std::weak_ptr<Shared>& self);
  std::string write_batch(const std::string& records, const StateImage& next);
};

std::uint64_t StateFile::Shared::queue(std::span<const banks::WrittenValue> write) {
  ++kept;
  thread.hand_over(
      [&] {
        for (std::size_t i = 0; i < write.size(); ++i) queued.push_back({persisted(write[i]), i + 1 < write.size()});
        queued_up_to = kept;
      },
      true);
  uncommitted.push_back({kept, std::vector(write.begin(), write.end())});
  counters.records += write.size();
  return kept;
}

// Batches complete in the order they were written, one post each: a failed batch refuses
// its own writes only, commits and acknowledges none of them, and the next batch (a
// rewrite, see write_batch) still commits and acknowledges its own. The outage is logged
// as the monitor's files are (monitor/write_outage.hpp): once, and once it is over.
void StateFile::Shared::synced(std::uint64_t sequence, std::string error, const std::weak_ptr<Shared>& self) {
  finished_batches.push_back({sequence, std::move(error)});
  if (!finishing) finish_slice(self);
}

// One sync may hold thousands of writes (a burst of MQTT commands: issue 43, finding 6);
// committing and answering them all in one go kept a Modbus request waiting for seconds.
// So a slice of them at a time, the rest posted behind whatever else the loop has to do;
// a later batch waits for the one before it, so the order kept is the order committed.
void StateFile::Shared::finish_slice(const std::weak_ptr<Shared>& self) {
  finishing = false;
  if (finished_batches.empty()) return;
  const auto alive = self.lock();  // an answer may let go of the StateFile: slice is measured after
  const auto began = TurnDeadline::Clock::now();
  std::size_t taken = 0;
  auto& batch = finished_batches.front();
  const bool ok = batch.error.empty();
  const auto now = monitor::WriteOutage::Clock::now();
  if (!std::exchange(batch.begun, true)) {
    if (ok) {
      ++counters.syncs;
      if (outage.failing())
        if (const auto recovery = outage.succeeded(now))
          spdlog::info("state: {} takes writes again; {} writes refused over {:.1f} s", path.string(),
                       recovery->failed_writes, std::chrono::duration<double>(recovery->lasted).count());
    } else {
      ++counters.failures;
      // The Error bit before the first of its writes is answered.
      if (outcome.refused) outcome.refused();
    }
  }
  // Committed in the order kept, all of a slice before any of its answers: an answer may
  // be followed at once by a read that must see its write.
  std::uint64_t done_up_to = 0;
  for (; taken < slice.next() && !uncommitted.empty() && uncommitted.front().sequence <= batch.sequence; ++taken) {
    done_up_to = uncommitted.front().sequence;
    if (ok && outcome.commit) outcome.commit(uncommitted.front().values);
    if (!ok && outage.failed(now))
      spdlog::error("state: cannot write {}: {}; writes are refused (exception 04) and change nothing until it "
                    "can (logged once, and when it has taken writes again for {} s)",
                    path.string(), batch.error,
                    std::chrono::duration_cast<std::chrono::seconds>(monitor::WriteOutage::default_settle).count());
    uncommitted.pop_front();
  }
  const bool batch_done = uncommitted.empty() || uncommitted.front().sequence > batch.sequence;
  if (batch_done) done_up_to = batch.sequence;
  if (ok) durable = done_up_to;
  // A callback may keep more, or ask when_durable: the ready ones leave the queue first.
  std::vector<Done> ready;
  while (!waiters.empty() && waiters.front().first <= done_up_to) {
    ready.push_back(std::move(waiters.front().second));
    waiters.pop_front();
  }
  if (batch_done) finished_batches.pop_front();
  if (!finished_batches.empty()) {
    finishing = true;
    asio::post(io, [self] {
      if (const auto shared = self.lock()) shared->finish_slice(self);
    });
  }
  for (auto& done : ready) done(ok);
  slice.took(taken, TurnDeadline::Clock::now() - began);
}

// `next`: what the file holds once `records` are on it.
std::string StateFile::Shared::write_batch(const std::string& records, const StateImage& next) {
  try {
    if (rewrite || size + records.size() > compact_at) {
      const auto content = state::encode_image(next);
      fd = replace_file(path, content);
      size = content.size();
      rewrite = false;
    } else {
      write_all(fd.get(), records);
      sync_data(fd.get());
      size += records.size();
    }
    return {};
  } catch (const std::system_error& e) {
    if (fd.get() >= 0) (void)!::ftruncate(fd.get(), static_cast<off_t>(size));  // best effort; the rewrite repairs
    rewrite = true;
    return e.what();
  }
}

// Everything queued, in one batch; the last turn writes what is left, so a clean stop
// loses nothing.
void StateFile::Shared::turn(const std::weak_ptr<Shared>& self) {
  std::uint64_t sequence = 0;
  thread.take([&] {
    batch.swap(queued);
    sequence = queued_up_to;
  });
  if (batch.empty()) return;
  records.clear();
  auto next = image;
  for (const auto& record : batch) {
    next.apply(record.value);
    records += state::encode_record(record.value, record.continued);
  }
  batch.clear();
  auto error = write_batch(records, next);
  if (error.empty()) image = next;
  asio::post(io, [self, sequence, error = std::move(error)]() mutable {
    if (const auto shared = self.lock()) shared->synced(sequence, std::move(error), self);
  });
}

StateFile::StateFile(asio::io_context& io, std::filesystem::path path) : path_(std::move(path)) {
  try {
    restored_ = load(path_);
    const auto content = state::encode_image(restored_);
    auto fd = replace_file(path_, content);
    shared_ = std::make_shared<Shared>(io, path_, restored_, std::move(fd), content.size());
  } catch (const std::exception& e) {
    throw std::runtime_error("state file " + path_.string() + ": " + e.what());
  }
  shared_->thread.start([shared = shared_.get(), weak = std::weak_ptr<Shared>(shared_)](bool) {
    shared->turn(weak);
    return std::optional<platform::JournalThread::Clock::time_point>();  // woken by each write
  });
  spdlog::info("state: {} holds {} values", path_.string(), restored_.values().size());
}

StateFile::~StateFile() { shared_->thread.stop(); }

void StateFile::set_outcome(Outcome outcome) { shared_->outcome = std::move(outcome); }

std::uint64_t StateFile::keep(std::span<const banks::WrittenValue> write) { return shared_->queue(write); }

std::optional<std::uint16_t> StateFile::pending(banks::BankId bank, std::uint16_t offset) const {
  const auto& uncommitted = shared_->uncommitted;
  for (auto write = uncommitted.rbegin(); write != uncommitted.rend(); ++write)
    for (auto value = write->values.rbegin(); value != write->values.rend(); ++value)
      if (value->bank == bank && value->offset == offset) return value->value;
  return std::nullopt;
}

void StateFile::when_durable(std::uint64_t sequence, Done done) {
  if (sequence <= shared_->durable) return done(true);
  shared_->waiters.emplace_back(sequence, std::move(done));
}

StateFile::Counters StateFile::counters() const { return shared_->counters; }

}  // namespace unima::io
