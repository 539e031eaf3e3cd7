#pragma once
// Reads a log file line by line and follows it like `tail -F`: across rotations (the path
// names a new file) and truncations. For `unima-bridge monitor --follow`.

#include <sys/types.h>

#include <functional>
#include <string>
#include <string_view>

namespace unima::cli {

class LogFollower {
 public:
  using LineFn = std::function<void(std::string_view line)>;

  explicit LogFollower(std::string path) : path_(std::move(path)) {}
  ~LogFollower();
  LogFollower(const LogFollower&) = delete;
  LogFollower& operator=(const LogFollower&) = delete;

  /// Opens the file; false (errno set) when it cannot, e.g. it does not exist yet.
  bool open();
  bool is_open() const { return fd_ >= 0; }

  /// Hands every complete line that arrived since the last call to `each_line` (without
  /// its "\n"; a partial last line waits for its end). When the path has been rotated
  /// away, the rest of the old file comes first, then a file rotated away unseen (path.1,
  /// when two rotations passed between calls), then the new file from its start.
  void poll(const LineFn& each_line);

 private:
  void read_available(const LineFn& each_line);
  void read_whole(const std::string& path, const LineFn& each_line);
  void flush_partial(const LineFn& each_line);

  std::string path_;
  int fd_ = -1;
  dev_t device_ = 0;
  ino_t inode_ = 0;
  std::string partial_;
};

}  // namespace unima::cli
