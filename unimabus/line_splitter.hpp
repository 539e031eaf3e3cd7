#pragma once
// Splits a byte stream into newline-terminated lines, for the feed protocol. Fed whatever
// arrived; a line longer than the limit is discarded up to its newline and reported once,
// so one bad writer cannot make the reader hold unbounded memory.

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>

namespace unima::unimabus {

class LineSplitter {
 public:
  explicit LineSplitter(std::size_t max_line = 64 * 1024) : max_line_(max_line) {}

  /// Calls on_line(line) for each complete line (without "\n" or a trailing "\r") and
  /// on_overlong() once for each line that exceeded the limit.
  void feed(std::string_view bytes, const std::function<void(std::string_view)>& on_line,
            const std::function<void()>& on_overlong);

 private:
  std::size_t max_line_;
  std::string partial_;
  bool discarding_ = false;
};

}  // namespace unima::unimabus
