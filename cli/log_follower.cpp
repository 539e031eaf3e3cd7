#include "cli/log_follower.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>

namespace unima::cli {

namespace {

// Splits what was read into lines; the unfinished end stays in `partial`.
void split_lines(std::string& partial, std::string_view chunk, const LogFollower::LineFn& each_line) {
  while (!chunk.empty()) {
    const auto newline = chunk.find('\n');
    if (newline == std::string_view::npos) {
      partial.append(chunk);
      return;
    }
    if (partial.empty()) {
      each_line(chunk.substr(0, newline));
    } else {
      partial.append(chunk.substr(0, newline));
      each_line(partial);
      partial.clear();
    }
    chunk.remove_prefix(newline + 1);
  }
}

void read_to_end(int fd, std::string& partial, const LogFollower::LineFn& each_line) {
  char buffer[65536];
  while (true) {
    const auto n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    split_lines(partial, std::string_view(buffer, static_cast<std::size_t>(n)), each_line);
  }
}

}  // namespace

LogFollower::~LogFollower() {
  if (fd_ >= 0) ::close(fd_);
}

bool LogFollower::open() {
  const int fd = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  struct stat st{};
  ::fstat(fd, &st);
  if (fd_ >= 0) ::close(fd_);
  fd_ = fd;
  device_ = st.st_dev;
  inode_ = st.st_ino;
  return true;
}

void LogFollower::read_available(const LineFn& each_line) { read_to_end(fd_, partial_, each_line); }

void LogFollower::read_whole(const std::string& path, const LineFn& each_line) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return;
  std::string partial;
  read_to_end(fd, partial, each_line);
  if (!partial.empty()) each_line(partial);
  ::close(fd);
}

void LogFollower::flush_partial(const LineFn& each_line) {
  if (!partial_.empty()) each_line(partial_);
  partial_.clear();
}

void LogFollower::poll(const LineFn& each_line) {
  if (fd_ < 0 && !open()) return;
  read_available(each_line);

  struct stat now{};
  if (::stat(path_.c_str(), &now) != 0) return;  // between the rename and the new file
  if (now.st_dev == device_ && now.st_ino == inode_) {
    struct stat open_file{};
    if (::fstat(fd_, &open_file) == 0 && open_file.st_size < ::lseek(fd_, 0, SEEK_CUR)) {
      ::lseek(fd_, 0, SEEK_SET);  // truncated in place
      partial_.clear();
      read_available(each_line);
    }
    return;
  }
  // Rotated: nothing more is written to the old file once the path names another one.
  read_available(each_line);
  flush_partial(each_line);
  struct stat previous{};
  const auto rotated = path_ + ".1";
  if (::stat(rotated.c_str(), &previous) == 0 && !(previous.st_dev == device_ && previous.st_ino == inode_) &&
      !(previous.st_dev == now.st_dev && previous.st_ino == now.st_ino))
    read_whole(rotated, each_line);
  if (open()) read_available(each_line);
}

}  // namespace unima::cli
