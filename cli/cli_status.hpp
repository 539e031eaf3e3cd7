#pragma once
// `unima-bridge status`: asks the daemon's status socket and shows the front panel
// (seed 004 §8 LEDs, capture indicators) and the counters, or the JSON document.

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace unima::cli {

/// `args` are the words after "status"; returns the exit code.
int status_command(const std::vector<std::string>& args);

/// The document of Bridge::status_document as the operator reads it.
std::string render_status_panel(const nlohmann::json& status);

}  // namespace unima::cli
