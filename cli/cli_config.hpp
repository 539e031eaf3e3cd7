#pragma once
// `unima-bridge config apply FILE | show | history | revert`: a config from the command line
// through the daemon's one flow of changes (SPEC §19), over its control socket.

#include <string>
#include <vector>

namespace unima::cli {

/// `args` are the words after "config"; returns the exit code: 0 applied (or shown), 1
/// refused, rolled back, busy or unreachable, 2 a usage error.
int config_command(const std::vector<std::string>& args);

}  // namespace unima::cli
