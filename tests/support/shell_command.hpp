#pragma once
// A shell command run to its end with its output captured: the CLI under test, and the
// command-line tools of the real peers (mosquitto_pub, openssl, promtool).

#include <string>

namespace unima::test_support {

struct CommandResult {
  int status;          // the exit code, -1 when killed
  std::string output;  // standard output and error together
};
CommandResult run(const std::string& command);

}  // namespace unima::test_support
