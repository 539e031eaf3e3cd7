#include "io/durable_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <ctime>
#include <stdexcept>
#include <system_error>

namespace unima::io {
namespace {

[[noreturn]] void throw_errno(const std::string& what) { throw std::system_error(errno, std::generic_category(), what); }

std::string utc_stamp() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  ::gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y%m%dT%H%M%SZ", &utc);
  return text;
}

}  // namespace

// The rename itself is made durable by syncing the directory that holds the name.
void sync_directory(const std::filesystem::path& file) {
  const auto dir = file.parent_path().empty() ? std::filesystem::path(".") : file.parent_path();
  const Descriptor fd(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  if (fd.get() < 0) throw_errno("open " + dir.string());
  if (::fsync(fd.get()) != 0) throw_errno("fsync " + dir.string());
}

Descriptor& Descriptor::operator=(Descriptor&& other) noexcept {
  if (this != &other) {
    reset();
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

void Descriptor::reset() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

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
  bytes.reserve(static_cast<std::size_t>(st.st_size));
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

// A temporary that could not be written is removed: on a full disk it would only hold the
// room the next try needs.
Descriptor replace_file(const std::filesystem::path& path, std::string_view content, FileAccess access) {
  return replace_file(path, [content](int fd) { write_all(fd, content); }, access);
}

Descriptor replace_file(const std::filesystem::path& path, const std::function<void(int fd)>& write, FileAccess access) {
  // A directory that is not there yet is made, as for the monitor's file: `check` and the
  // start's log warn of it (config/host_check), in case its path was mistyped.
  if (const auto directory = path.parent_path(); !directory.empty()) {
    std::error_code made;
    std::filesystem::create_directories(directory, made);
    if (made) throw std::system_error(made, "create the directory " + directory.string());
  }
  auto temporary = path;
  temporary += ".tmp";
  const bool owner_only = access == FileAccess::owner_only;
  Descriptor fd(::open(temporary.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_APPEND | O_NOFOLLOW | O_CLOEXEC,
                       owner_only ? 0600 : 0640));
  if (fd.get() < 0) throw_errno("create " + temporary.string());
  try {
    // A temporary left by a crash keeps the mode it was made with: owner_only holds anyway.
    if (owner_only && ::fchmod(fd.get(), 0600) != 0) throw_errno("chmod " + temporary.string());
    write(fd.get());
    sync_data(fd.get());
    if (::rename(temporary.c_str(), path.c_str()) != 0) throw_errno("rename " + temporary.string());
  } catch (const std::system_error&) {
    ::unlink(temporary.c_str());
    throw;
  }
  sync_directory(path);
  return fd;
}

std::filesystem::path set_aside(const std::filesystem::path& path) {
  auto aside = path;
  aside += ".corrupt-" + utc_stamp();
  if (::rename(path.c_str(), aside.c_str()) != 0) throw_errno("cannot keep it aside as " + aside.string());
  return aside;
}

}  // namespace unima::io
