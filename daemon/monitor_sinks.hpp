#pragma once
// Where the monitor writer puts its lines: a size-rotated file, or standard output.
// Called on the writer thread only (daemon/monitor_writer.hpp).

#include <cstdint>
#include <string>
#include <string_view>

#include "daemon/monitor_writer.hpp"

namespace unima::daemon {

/// Appends to `path`; before a line would make it larger than max_size, renames
/// path -> path.1 -> ... -> path.<max_files> (the oldest is dropped) and starts a new file,
/// so `tail -F path` and `unima-bridge monitor --follow` go on with the new one.
/// A line is never split between two files.
class RotatingFileSink : public MonitorSink {
 public:
  /// Opens (creating the directory if needed); throws std::runtime_error naming the path.
  RotatingFileSink(std::string path, std::uint64_t max_size, unsigned max_files);
  ~RotatingFileSink() override;

  void write(std::string_view lines) override;
  std::uint64_t size() const { return size_; }

 private:
  bool open();
  void rotate();
  void append(std::string_view bytes);

  std::string path_;
  std::uint64_t max_size_;
  unsigned max_files_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
  bool failing_ = false;  // a write error was logged; the next success is logged too
};

/// The daemon's standard output (the journal under systemd).
class StdoutSink : public MonitorSink {
 public:
  void write(std::string_view lines) override;

 private:
  bool failed_ = false;  // logged once
};

}  // namespace unima::daemon
