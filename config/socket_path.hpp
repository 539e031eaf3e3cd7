#pragma once
// A unix socket's path on the file system (SPEC §10, "paths are not trusted"). Binding
// needs the path free, so the socket file a previous run left behind is removed first. A
// path that names anything else — a file, a directory, a symbolic link — was put there by
// someone, perhaps to have the daemon delete it: that is an error, and nothing is removed.
// config::check_on_host asks once the config is parsed, so `unima-bridge check` refuses
// what the daemon would; the daemon asks again right before it removes anything, as the
// file system may have changed.

#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace unima::config {

/// A path the daemon will not use: a start-up error, and a reload that keeps the running
/// config. what() names the config key.
class PathRefused : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Why the daemon must not bind a socket at `path`, e.g. "/run/x names a regular file, not a
/// socket"; nullopt when nothing or a socket is there (and when the path cannot be looked
/// at: the bind then says why).
std::optional<std::string> socket_path_conflict(const std::string& path);

/// Frees `path` to bind: removes a socket file there, never anything else. Throws
/// PathRefused, naming `key`, when something other than a socket is there.
void clear_socket_path(const std::string& path, std::string_view key);

/// Removes `path` if it is a socket (a listener's own, when it stops); anything that took
/// its place meanwhile stays.
void remove_socket_file(const std::string& path);

}  // namespace unima::config
