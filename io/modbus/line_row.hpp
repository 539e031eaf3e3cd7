#pragma once
// A line's row of the status document (SPEC §18) from its config and what its port counts:
// the slave service and the master service describe their lines alike.

#include "config/config.hpp"
#include "status/line_status.hpp"

namespace unima::io {

status::LineStatus line_row(const config::LineConfig& line, bool open, const status::LineCounters& counters,
                            std::size_t queue);

}  // namespace unima::io
