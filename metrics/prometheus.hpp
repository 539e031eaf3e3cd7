#pragma once
// /metrics (SPEC §13): the status document (status/document.hpp, filled by `Bridge::status`
// in app/bridge and each service's `describe`) in Prometheus' text exposition
// format, so the counters have one source and Prometheus, the CLI and the browser page
// never disagree. Each family's name, type and help are declared beside the typed part of
// the document it reads (a `status::Statistic`, status/statistic.hpp); this is the list
// of parts in the exposition's order. Names start with `unima_bridge_`; every family has
// its HELP and TYPE lines; counters end in `_total`.
//
// Pure: a typed document in, text out.

#include <string>

#include "status/document.hpp"

namespace unima::metrics {

/// The exposition of `status`: the parts it lacks, and its null values, are left out,
/// never made up.
std::string prometheus_text(const status::Document& status);

/// The Content-Type of that text.
inline constexpr const char* prometheus_content_type = "text/plain; version=0.0.4; charset=utf-8";

}  // namespace unima::metrics
