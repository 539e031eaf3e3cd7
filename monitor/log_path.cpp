#include "monitor/log_path.hpp"

#include <sys/stat.h>

namespace unima::monitor {

std::optional<std::string> refused_log_path(const std::string& path) {
  struct stat st{};
  if (::lstat(path.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return std::nullopt;
  return path + " is a symbolic link; the bridge never appends to a log through one";
}

}  // namespace unima::monitor
