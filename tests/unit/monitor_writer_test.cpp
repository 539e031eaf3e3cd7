// The monitor's writer and sinks (monitor/): a blocked writer never blocks the ports — the
// queue fills, the rest is dropped, counted, and the log says so; the file sink rotates
// by size without splitting lines.

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include "monitor/monitor_sinks.hpp"
#include "monitor/monitor_writer.hpp"
#include "tests/support/temp_files.hpp"

namespace unima::monitor {
using namespace unima::modbus;
namespace {

using namespace std::chrono_literals;
using Bytes = std::vector<std::uint8_t>;

// A sink whose first write blocks until released: a disk that hangs.
struct Gate {
  std::mutex mutex;
  std::condition_variable changed;
  bool entered = false;
  bool released = false;
  std::string text;
};

class BlockingSink : public MonitorSink {
 public:
  explicit BlockingSink(std::shared_ptr<Gate> gate) : gate_(std::move(gate)) {}
  void write(std::string_view lines) override {
    std::unique_lock lock(gate_->mutex);
    gate_->entered = true;
    gate_->changed.notify_all();
    gate_->changed.wait(lock, [&] { return gate_->released; });
    gate_->text += lines;
  }

 private:
  std::shared_ptr<Gate> gate_;
};

const Bytes query = {0x12, 0x34, 0x00, 0x00, 0x00, 0x06, 0x01, 0x04, 0x00, 0x11, 0x00, 0x02};
const Bytes response = {0x12, 0x34, 0x00, 0x00, 0x00, 0x07, 0x01, 0x04, 0x04, 0x00, 0x50, 0x7F, 0xFF};

modbus::Transaction transaction() {
  return {modbus::PortKind::tcp, "127.0.0.1:5000", std::chrono::system_clock::time_point{},
          modbus::TransactionState::done, query, response};
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(MonitorWriter, ABlockedWriterMakesPushesDropAndCountNeverWait) {
  auto gate = std::make_shared<Gate>();
  std::vector<std::unique_ptr<MonitorSink>> sinks;
  sinks.push_back(std::make_unique<BlockingSink>(gate));
  MonitorWriter::Options options;
  options.capacity = 8;
  options.batch_window = 0ms;
  MonitorWriter writer(std::move(sinks), options);

  ASSERT_TRUE(writer.push(transaction(), 0));
  {
    std::unique_lock lock(gate->mutex);
    ASSERT_TRUE(gate->changed.wait_for(lock, 5s, [&] { return gate->entered; })) << "the writer never wrote";
  }
  // The writer holds one slot while it is stuck in the sink: 7 more fit, 3 are dropped.
  std::vector<bool> accepted;
  for (std::uint8_t ix = 1; ix <= 10; ++ix) accepted.push_back(writer.push(transaction(), ix));
  EXPECT_EQ(accepted, (std::vector<bool>{true, true, true, true, true, true, true, false, false, false}));
  EXPECT_EQ(writer.dropped(), 3u);

  {
    std::lock_guard lock(gate->mutex);
    gate->released = true;
  }
  gate->changed.notify_all();
  writer.stop();
  EXPECT_EQ(writer.written(), 8u);
  EXPECT_EQ(writer.dropped(), 3u);
  const auto lines = lines_of(gate->text);
  ASSERT_EQ(lines.size(), 9u) << gate->text;
  for (std::size_t i = 0; i < 8; ++i)
    EXPECT_NE(lines[i].find(" Ix=" + std::to_string(i) + " "), std::string::npos) << lines[i];
  EXPECT_NE(lines[8].find(" monitor Dropped=3"), std::string::npos) << lines[8];
  EXPECT_FALSE(writer.push(transaction(), 11));  // stopped
}

TEST(MonitorWriter, AnUnblockedWriterWritesEveryLineInOrder) {
  auto gate = std::make_shared<Gate>();
  gate->released = true;
  std::vector<std::unique_ptr<MonitorSink>> sinks;
  sinks.push_back(std::make_unique<BlockingSink>(gate));
  MonitorWriter::Options options;
  options.capacity = 1000;
  options.format = monitor::MonitorFormat::json;
  MonitorWriter writer(std::move(sinks), options);
  for (int i = 0; i < 500; ++i) ASSERT_TRUE(writer.push(transaction(), static_cast<std::uint8_t>(i)));
  writer.stop();
  const auto lines = lines_of(gate->text);
  ASSERT_EQ(lines.size(), 500u);
  for (std::size_t i = 0; i < lines.size(); ++i)
    EXPECT_NE(lines[i].find("\"ix\":" + std::to_string(i % 256) + ","), std::string::npos) << lines[i];
  EXPECT_EQ(writer.dropped(), 0u);
}

// A sink that counts lines and the drops the log reports.
class CountingSink : public MonitorSink {
 public:
  void write(std::string_view lines) override {
    for (const auto& line : lines_of(std::string(lines))) {
      if (const auto at = line.find(" monitor Dropped="); at != std::string::npos)
        reported_drops += std::stoull(line.substr(at + 17));
      else
        ++transactions;
    }
  }
  std::uint64_t transactions = 0;
  std::uint64_t reported_drops = 0;
};

// The ring is shared without a lock on the pushing side: under a flood that keeps it full,
// every transaction is either written once or dropped and reported once.
TEST(MonitorWriter, UnderAFloodEveryTransactionIsWrittenOrCountedExactlyOnce) {
  for (const auto window : {0ms, 1ms}) {
    auto sink = std::make_unique<CountingSink>();
    auto* counted = sink.get();
    std::vector<std::unique_ptr<MonitorSink>> sinks;
    sinks.push_back(std::move(sink));
    MonitorWriter::Options options;
    options.capacity = 64;
    options.batch_window = window;
    MonitorWriter writer(std::move(sinks), options);
    constexpr std::uint64_t pushes = 200'000;
    std::uint64_t accepted = 0;
    for (std::uint64_t i = 0; i < pushes; ++i) accepted += writer.push(transaction(), static_cast<std::uint8_t>(i));
    writer.stop();
    EXPECT_EQ(writer.written(), accepted);
    EXPECT_EQ(writer.dropped(), pushes - accepted);
    EXPECT_EQ(counted->transactions, accepted);
    EXPECT_LE(counted->reported_drops, writer.dropped());  // the last drops may come after the last batch
    EXPECT_GT(accepted, 0u);
  }
}

// A sink that keeps everything and notes a write that does not end with a whole line.
class RecordingSink : public MonitorSink {
 public:
  explicit RecordingSink(std::shared_ptr<std::string> text) : text_(std::move(text)) {}
  void write(std::string_view lines) override {
    if (lines.empty() || lines.back() != '\n') ++broken_writes;
    *text_ += lines;
  }
  int broken_writes = 0;

 private:
  std::shared_ptr<std::string> text_;
};

// Transactions of every length go round a small ring many times: each line the writer
// hands on is whole, in order, and says exactly what was pushed (frames longer than an ADU cut, Rc
// still their size; a peer longer than 64 characters cut).
TEST(MonitorWriter, TransactionsOfEveryLengthComeOutWholeAndInOrder) {
  for (const auto format : {monitor::MonitorFormat::text, monitor::MonitorFormat::json}) {
    auto text = std::make_shared<std::string>();
    auto sink = std::make_unique<RecordingSink>(text);
    const auto* recorded = sink.get();
    std::vector<std::unique_ptr<MonitorSink>> sinks;
    sinks.push_back(std::move(sink));
    MonitorWriter::Options options;
    options.capacity = 16;
    options.batch_window = 0ms;
    options.format = format;
    MonitorWriter writer(std::move(sinks), options);

    struct Pushed {
      std::uint8_t ix;
      Bytes query;
      Bytes response;
      std::string peer;
    };
    std::vector<Pushed> accepted;
    for (int i = 0; i < 3000; ++i) {
      Pushed p;
      p.ix = static_cast<std::uint8_t>(i);
      p.query = query;
      if (i % 7 == 0) p.query.resize(300, 0x5A);  // longer than any ADU
      p.response.resize(static_cast<std::size_t>(i * 37 % 301));
      for (std::size_t b = 0; b < p.response.size(); ++b) p.response[b] = static_cast<std::uint8_t>(b * 7 + i);
      p.peer = i % 11 == 0 ? std::string(100, '9') : "10.0.0." + std::to_string(i % 200) + ":" + std::to_string(i);
      const modbus::Transaction t{modbus::PortKind::tcp, p.peer, std::chrono::system_clock::time_point{},
                                  modbus::TransactionState::done, p.query, p.response};
      // A full ring is waited out here (bounded), so that every length goes through.
      bool taken = false;
      for (int attempt = 0; !taken && attempt < 20'000; ++attempt) {
        taken = writer.push(t, p.ix);
        if (!taken) std::this_thread::sleep_for(50us);
      }
      ASSERT_TRUE(taken) << "the writer never made room";
      accepted.push_back(std::move(p));
    }
    writer.stop();
    EXPECT_EQ(recorded->broken_writes, 0);
    EXPECT_EQ(writer.written(), accepted.size());

    std::vector<std::string> lines;
    for (const auto& line : lines_of(*text))
      if (line.find("\"monitor\"") == std::string::npos && line.find(" monitor Dropped=") == std::string::npos)
        lines.push_back(line);
    ASSERT_EQ(lines.size(), accepted.size());
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const auto parsed = monitor::parse_monitor_line(lines[i]);
      ASSERT_TRUE(parsed) << lines[i];
      const auto& p = accepted[i];
      EXPECT_EQ(parsed->ix, p.ix);
      EXPECT_EQ(parsed->rc, p.query.size());
      EXPECT_EQ(parsed->port, "tcp:" + p.peer.substr(0, 64));
      const auto kept = std::min<std::size_t>(p.response.size(), MonitorWriter::max_frame);
      EXPECT_EQ(parsed->response, Bytes(p.response.begin(), p.response.begin() + static_cast<std::ptrdiff_t>(kept)))
          << lines[i];
    }
  }
}

// A TLS client's port field carries its certificate's role, text the client chose: a role
// holding a newline, a carriage return, an escape sequence or spaces comes out as one
// line, its field escaped as log text is, so it neither forges a line nor shifts the
// fields after it (row 5 of issue 29); the JSON line keeps the role itself, as JSON.
TEST(MonitorWriter, APeerNameIsEscapedSoItCannotForgeALineOrAField) {
  const std::string role = "op\n2026-11-22T00:00:00Z tcp:x Ix=0\r\x1b[2J x";  // the peer fits 64 bytes
  const std::string peer = role + "@127.0.0.1:5000";
  for (const auto format : {monitor::MonitorFormat::text, monitor::MonitorFormat::json}) {
    auto text = std::make_shared<std::string>();
    std::vector<std::unique_ptr<MonitorSink>> sinks;
    sinks.push_back(std::make_unique<RecordingSink>(text));
    MonitorWriter::Options options;
    options.batch_window = 0ms;
    options.format = format;
    MonitorWriter writer(std::move(sinks), options);
    ASSERT_TRUE(writer.push({modbus::PortKind::tls, peer, std::chrono::system_clock::time_point{},
                             modbus::TransactionState::done, query, response},
                            3));
    writer.stop();

    ASSERT_EQ(lines_of(*text).size(), 1u) << *text;
    EXPECT_EQ(text->find('\r'), std::string::npos) << *text;
    EXPECT_EQ(text->find('\x1b'), std::string::npos) << *text;
    const auto parsed = monitor::parse_monitor_line(*text);
    ASSERT_TRUE(parsed) << *text;
    EXPECT_EQ(parsed->ix, 3);
    EXPECT_EQ(parsed->response, response);
    if (format == monitor::MonitorFormat::text)
      EXPECT_EQ(parsed->port,
                "tls:op\\n2026-11-22T00:00:00Z\\x20tcp:x\\x20Ix=0\\r\\x1B[2J\\x20x@127.0.0.1:5000");
    else
      EXPECT_EQ(parsed->port, "tls:" + peer);
  }
}

using test_support::read_file;
using test_support::TempDir;

std::string numbered_line(int n) {  // 100 bytes with its newline
  auto line = "line " + std::to_string(n);
  line.resize(99, '.');
  return line + "\n";
}

TEST(RotatingFileSink, RotatesBySizeKeepingMaxFilesAndWholeLines) {
  TempDir dir;
  const auto path = dir.path() / "sub" / "monitor.log";  // the directory is created
  RotatingFileSink sink(path.string(), 350, 2);
  std::string batch;
  for (int n = 0; n < 7; ++n) batch += numbered_line(n);
  sink.write(batch);  // 0-2 | 3-5 | 6
  for (int n = 7; n < 12; ++n) sink.write(numbered_line(n));  // ... 6-8 | 9-11
  sink.flush();

  EXPECT_EQ(read_file(path), numbered_line(9) + numbered_line(10) + numbered_line(11));
  EXPECT_EQ(read_file(path.string() + ".1"), numbered_line(6) + numbered_line(7) + numbered_line(8));
  EXPECT_EQ(read_file(path.string() + ".2"), numbered_line(3) + numbered_line(4) + numbered_line(5));
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".3"));
}

TEST(RotatingFileSink, AppendsToAnExistingFileAndCountsItsSize) {
  TempDir dir;
  const auto path = dir.path() / "monitor.log";
  std::ofstream(path) << numbered_line(0) << numbered_line(1);
  {
    RotatingFileSink sink(path.string(), 300, 1);
    EXPECT_EQ(sink.size(), 200u);
    sink.write(numbered_line(2));
    sink.write(numbered_line(3));
  }
  EXPECT_EQ(read_file(path), numbered_line(3));
  EXPECT_EQ(read_file(path.string() + ".1"), numbered_line(0) + numbered_line(1) + numbered_line(2));
}

// Blocks on disk are taken a step ahead of the lines (cheaper appends), never shown in the
// size readers see, and given back when the sink closes.
TEST(RotatingFileSink, ReservesBlocksAheadWithoutChangingTheSizeAndFreesThemOnClose) {
  TempDir dir;
  const auto path = dir.path() / "monitor.log";
  const auto allocated = [&] {
    struct stat st{};
    EXPECT_EQ(::stat(path.c_str(), &st), 0);
    return static_cast<std::uint64_t>(st.st_blocks) * 512;
  };
  {
    RotatingFileSink sink(path.string(), 1 << 20, 1);
    sink.write(numbered_line(0));
    sink.flush();
    EXPECT_EQ(std::filesystem::file_size(path), 100u);
    EXPECT_EQ(allocated(), 1u << 20) << "reserved up to max_size, which is less than a step";
  }
  EXPECT_EQ(read_file(path), numbered_line(0));
  EXPECT_LT(allocated(), 64u * 1024);
}

TEST(RotatingFileSink, AFileThatCannotBeOpenedIsAnErrorNamingIt) {
  TempDir dir;
  std::ofstream(dir.path() / "plain") << "x";
  const auto path = (dir.path() / "plain" / "monitor.log").string();  // under a file
  try {
    RotatingFileSink sink(path, 1000, 1);
    FAIL() << "opened";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "monitor.file: cannot open " + path + ": Not a directory");
  }
}

}  // namespace
}  // namespace unima::monitor
