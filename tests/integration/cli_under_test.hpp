#pragma once
// The `unima-bridge` the CLI tests run: this build's, or UNIMA_TEST_BRIDGE_CLI's (the filed
// commit's, to show a test fails there), as the harness takes UNIMA_TEST_BRIDGED for the daemon.

#include <cstdlib>
#include <string>

namespace unima::test {

inline std::string bridge_cli() {
  const char* other = std::getenv("UNIMA_TEST_BRIDGE_CLI");
  return other && *other ? other : UNIMA_BRIDGE_CLI;
}

}  // namespace unima::test
