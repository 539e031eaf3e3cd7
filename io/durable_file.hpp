#pragma once
// What the files the daemon keeps across restarts share (SPEC §10, §15): the state file
// (io/state_file) and the MQTT history buffer (io/mqtt/history_buffer) are each read
// whole at start, appended to and fdatasync'ed on a thread of their own, rewritten by
// atomic replace, and set aside as `<path>.corrupt-<UTC time>` when what they hold cannot
// be trusted. Each call blocks on the disk: those two make them on their own threads. The
// one exception is Sparkplug's bdSeq beside the state file (io/mqtt/sparkplug_service), a
// few bytes replaced once per MQTT CONNECT, at most once a second, on the loop.

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace unima::io {

/// A file descriptor that closes itself.
class Descriptor {
 public:
  explicit Descriptor(int fd = -1) : fd_(fd) {}
  Descriptor(Descriptor&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  Descriptor& operator=(Descriptor&& other) noexcept;
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  ~Descriptor() { reset(); }
  int get() const { return fd_; }
  void reset();

 private:
  int fd_;
};

/// The file's bytes; nullopt when there is none. Throws (std::system_error,
/// std::runtime_error) for a symbolic link, anything but a regular file, or a read error.
std::optional<std::string> read_if_present(const std::filesystem::path& path);
/// Throws std::system_error.
void write_all(int fd, std::string_view bytes);
/// fdatasync; throws std::system_error.
void sync_data(int fd);
/// Who may read a file the daemon keeps: its group too (0640 less the umask), or its owner
/// alone (0600 whatever the umask: a remote config holds passwords).
enum class FileAccess { owner_and_group, owner_only };

/// Atomic replace: `content` is on the disk under a temporary name before it takes the
/// file's name, so a crash leaves the old file or the new one, never a part of either.
/// Returns the new file, open for appending (and reading). Throws std::system_error.
Descriptor replace_file(const std::filesystem::path& path, std::string_view content,
                        FileAccess access = FileAccess::owner_and_group);
/// The same, the new content written by `write` to the descriptor it is given (a copy too
/// large to hold in memory at once).
Descriptor replace_file(const std::filesystem::path& path, const std::function<void(int fd)>& write,
                        FileAccess access = FileAccess::owner_and_group);
/// fsync of the directory that holds `file`: what makes a rename or an unlink there durable.
/// Throws std::system_error.
void sync_directory(const std::filesystem::path& file);
/// Renames `path` to `<path>.corrupt-<UTC time>` and returns that name (SPEC §10: a file
/// that cannot be trusted is kept for a human, not read and not overwritten). Throws
/// std::system_error when it cannot.
std::filesystem::path set_aside(const std::filesystem::path& path);

}  // namespace unima::io
