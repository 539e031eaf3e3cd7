#pragma once
// Which paths the bridge appends its logs to — the monitor file and the UnimaBUS recording
// (SPEC §10, "paths are not trusted"). Both are opened with O_NOFOLLOW: a symbolic link at
// the path is refused, never followed, since its target could be any file the daemon may
// write (and the monitor's rotation would truncate or rename it). Only the last component
// is looked at: the directories on the way are the administrator's.

#include <optional>
#include <string>

namespace unima::monitor {

/// Why the bridge will not append to `path` (it is a symbolic link), or nullopt: nothing
/// there, or something the open will try (and tell what is wrong with). The loader asks,
/// so that `unima-bridge check` refuses what the daemon would.
std::optional<std::string> refused_log_path(const std::string& path);

}  // namespace unima::monitor
