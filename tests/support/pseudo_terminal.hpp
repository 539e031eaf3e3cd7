#pragma once
// A pseudo-terminal standing in for a serial line: the daemon opens the slave side through
// a link, a test, a simulator or a benchmark plays the other end on the master side. One
// way to open it raw (a fresh terminal echoes, and would answer the test's own bytes
// before the daemon has set it up) and to point a link at it.

#include <filesystem>
#include <string>

namespace unima::test_support {

struct PseudoTerminal {
  int master = -1;
  int slave = -1;     // kept open, so that the master side never sees a hang-up of its own
  std::string name;   // /dev/pts/N
};

/// Opens a raw pseudo-terminal, both descriptors close-on-exec; throws std::runtime_error.
PseudoTerminal open_raw_pseudo_terminal();

/// Points `link` at `name` by a rename, so a reader never sees it missing or half made.
void point_link_at(const std::filesystem::path& link, const std::string& name);

}  // namespace unima::test_support
