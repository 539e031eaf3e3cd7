#pragma once
// `unima-bridge monitor`: reads the monitor log, filters it, follows it (SPEC §5, §8).

#include <string>
#include <vector>

namespace unima::cli {

/// `args` are the words after "monitor"; returns the exit code.
int monitor_command(const std::vector<std::string>& args);

}  // namespace unima::cli
