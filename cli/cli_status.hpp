#pragma once
// `unima-bridge status`: asks the daemon's status socket and shows the front panel
// (seed 004 §8 LEDs, capture indicators) and the counters, or the JSON document.

#include <stdexcept>
#include <string>
#include <vector>

#include "status/document.hpp"

namespace unima::cli {

/// `args` are the words after "status"; returns the exit code.
int status_command(const std::vector<std::string>& args);

/// The daemon's status document as the operator reads it. Throws MissingPart when a part
/// every running daemon has is absent (another program on the socket, another version).
std::string render_status_panel(const status::Document& status);

struct MissingPart : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace unima::cli
