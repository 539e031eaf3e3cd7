#pragma once
// Where the monitor writer puts its lines: a size-rotated file, or standard output.
// Called on the writer thread only (monitor/monitor_writer.hpp).

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "monitor/file_appender.hpp"
#include "monitor/monitor_writer.hpp"
#include "monitor/write_outage.hpp"

namespace unima::monitor {

/// Appends to `path`; before a line would make it larger than max_size, renames
/// path -> path.1 -> ... -> path.<max_files> (the oldest is dropped) and starts a new file,
/// so `tail -F path` and `unima-bridge monitor --follow` go on with the new one.
/// A line is never split between two files. Lines may be held back until flush() (see
/// monitor/file_appender.hpp), never longer than FileAppender::tail_delay.
class RotatingFileSink : public MonitorSink {
 public:
  /// Opens (creating the directory if needed); throws std::runtime_error naming `key`, the
  /// config key of the path, and the path (a symbolic link is refused: monitor/log_path).
  /// `purpose` begins its log messages ("monitor", "unimabus record").
  RotatingFileSink(std::string path, std::uint64_t max_size, unsigned max_files,
                   FileAppender::Route route = FileAppender::Route::direct_where_possible,
                   std::string purpose = "monitor", std::string_view key = "monitor.file");
  ~RotatingFileSink() override;

  void write(std::string_view lines) override;
  void flush() override;
  std::uint64_t size() const { return file_ ? file_->size() : 0; }

 private:
  bool open();
  void close();
  void rotate();
  void append(std::string_view bytes);
  void write_failed();
  void write_succeeded();

  std::string path_;
  std::uint64_t max_size_;
  unsigned max_files_;
  FileAppender::Route route_;
  std::string purpose_;
  std::unique_ptr<FileAppender> file_;
  FileAppender::Stage spare_stage_;  // the closed file's, for the next one
  WriteOutage outage_;  // a full disk is logged once, and its end once
};

/// The daemon's standard output (the journal under systemd).
class StdoutSink : public MonitorSink {
 public:
  void write(std::string_view lines) override;

 private:
  bool failed_ = false;  // logged once
};

}  // namespace unima::monitor
