#pragma once
// Files the daemon keeps on the disk (the state file, Sparkplug's bdSeq beside it) and how
// each is written so that a crash leaves the old content or the new, never part of either.
// Blocking calls: the state file makes them on its own thread (io/state_file.cpp); the
// bdSeq file, a few bytes once per MQTT CONNECT, on the loop.

#include <unistd.h>

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace unima::io {

/// A file descriptor, closed with its owner.
class Descriptor {
 public:
  explicit Descriptor(int fd = -1) : fd_(fd) {}
  Descriptor(Descriptor&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  Descriptor& operator=(Descriptor&& other) noexcept {
    if (this != &other) {
      reset();
      fd_ = std::exchange(other.fd_, -1);
    }
    return *this;
  }
  ~Descriptor() { reset(); }
  int get() const { return fd_; }
  void reset() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_;
};

/// throws std::system_error with errno and `what`.
[[noreturn]] void throw_errno(const std::string& what);

/// The content of a regular file, nullopt when there is none; never through a symbolic
/// link. Throws std::runtime_error (what it is) or std::system_error.
std::optional<std::string> read_if_present(const std::filesystem::path& path);

void write_all(int fd, std::string_view bytes);
void sync_data(int fd);

/// Atomic replace: `content` is on the disk under a temporary name before it takes the
/// file's name, and the rename is synced too. Returns the new file, open for appending.
Descriptor replace_file(const std::filesystem::path& path, std::string_view content);

}  // namespace unima::io
