#include "io/durable_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <stdexcept>
#include <system_error>

namespace unima::io {

void throw_errno(const std::string& what) { throw std::system_error(errno, std::generic_category(), what); }

std::optional<std::string> read_if_present(const std::filesystem::path& path) {
  // Non-blocking, so that a FIFO put there (the config check refuses one) is not waited on.
  const Descriptor fd(::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC));
  if (fd.get() < 0) {
    if (errno == ENOENT) return std::nullopt;
    if (errno == ELOOP) throw std::runtime_error("is a symbolic link; give the file itself");
    throw_errno("cannot read it");
  }
  struct stat st{};
  if (::fstat(fd.get(), &st) != 0) throw_errno("cannot read it");
  if (!S_ISREG(st.st_mode)) throw std::runtime_error("is not a regular file");
  std::string bytes;
  char buffer[16384];
  while (true) {
    const auto n = ::read(fd.get(), buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw_errno("cannot read it");
    if (n == 0) return bytes;
    bytes.append(buffer, static_cast<std::size_t>(n));
  }
}

void write_all(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    const auto n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw_errno("write");
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
}

void sync_data(int fd) {
  if (::fdatasync(fd) != 0) throw_errno("fdatasync");
}

// The rename itself is made durable by syncing the directory that holds the name.
namespace {

void sync_directory(const std::filesystem::path& file) {
  const auto dir = file.parent_path().empty() ? std::filesystem::path(".") : file.parent_path();
  const Descriptor fd(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  if (fd.get() < 0) throw_errno("open " + dir.string());
  if (::fsync(fd.get()) != 0) throw_errno("fsync " + dir.string());
}

}  // namespace

// Atomic replace: the new content is on the disk under a temporary name before it takes
// the file's name, so a crash leaves the old file or the new one, never a part of either.
// Returns the new file, open for appending. A temporary that could not be written is
// removed: on a full disk it would only hold the room the next try needs.
Descriptor replace_file(const std::filesystem::path& path, std::string_view content) {
  auto temporary = path;
  temporary += ".tmp";
  Descriptor fd(::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_NOFOLLOW | O_CLOEXEC, 0640));
  if (fd.get() < 0) throw_errno("create " + temporary.string());
  try {
    write_all(fd.get(), content);
    sync_data(fd.get());
    if (::rename(temporary.c_str(), path.c_str()) != 0) throw_errno("rename " + temporary.string());
  } catch (const std::system_error&) {
    ::unlink(temporary.c_str());
    throw;
  }
  sync_directory(path);
  return fd;
}
}  // namespace unima::io
