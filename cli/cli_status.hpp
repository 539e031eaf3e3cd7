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

/// How the panel is drawn: in colour on a terminal (a lit LED green, the Error LED and
/// what needs looking at red), plain into a pipe or a file, or when NO_COLOR is set.
struct PanelStyle {
  bool colour = false;
};

/// Whether standard output takes colour: a terminal other than "dumb", and no NO_COLOR
/// (no-color.org) in the environment.
bool colour_on_stdout();

/// The daemon's status document as the operator reads it. Throws MissingPart when a part
/// every running daemon has is absent (another program on the socket, another version).
std::string render_status_panel(const status::Document& status, PanelStyle style = {});

struct MissingPart : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace unima::cli
