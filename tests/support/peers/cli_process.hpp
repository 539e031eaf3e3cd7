#pragma once
// The operator's `unima-bridge` CLI left running beside the daemon (`monitor --follow`):
// the built program itself, so that a test sees what the operator would on the terminal
// while the daemon goes on (rotating its log, say). A CLI run to its end is `run`.

#include <filesystem>
#include <string>
#include <vector>

#include "tests/support/child_process.hpp"

namespace unima::test_support {

/// `unima-bridge ARGS...` running beside the test, its output going to a file; ended with
/// SIGTERM when the object goes.
class CliProcess {
 public:
  CliProcess(const std::filesystem::path& output, std::vector<std::string> args);
  /// What it printed so far.
  std::string output() const;

 private:
  std::filesystem::path output_;
  ChildProcess process_;
};

}  // namespace unima::test_support
