#include "config/socket_path.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>

namespace unima::config {

namespace {

// lstat: a symbolic link is itself the problem, wherever it points.
std::optional<mode_t> file_type(const std::string& path) {
  struct stat st{};
  if (::lstat(path.c_str(), &st) != 0) return std::nullopt;
  return st.st_mode & S_IFMT;
}

std::string_view describe(mode_t type) {
  switch (type) {
    case S_IFREG: return "a regular file";
    case S_IFDIR: return "a directory";
    case S_IFLNK: return "a symbolic link";
    case S_IFIFO: return "a FIFO";
    case S_IFCHR: return "a character device";
    case S_IFBLK: return "a block device";
    default: return "something other than a socket";
  }
}

}  // namespace

std::optional<std::string> socket_path_conflict(const std::string& path) {
  const auto type = file_type(path);
  if (!type || *type == S_IFSOCK) return std::nullopt;
  return fmt::format("{} names {}, not a socket; the daemon never removes it to listen there", path, describe(*type));
}

void clear_socket_path(const std::string& path, std::string_view key) {
  if (auto conflict = socket_path_conflict(path)) throw PathRefused(fmt::format("{}: {}", key, *conflict));
  if (file_type(path)) ::unlink(path.c_str());
}

void remove_socket_file(const std::string& path) {
  if (file_type(path) == S_IFSOCK) ::unlink(path.c_str());
}

}  // namespace unima::config
