#pragma once
// A statistic of /metrics (SPEC §13), declared once beside the typed part of the status
// document it reads: its name, type and help, and the samples it takes from that part.
// ISC Kea's stats_mgr is the model — one registry of named statistics that every reader
// asks: metrics::prometheus_text lists each part's statistics and loops over them, and the
// part's JSON (`unima-bridge status --json`, /api/status, the CLI panel, the page) is
// written by the same struct. A new counter is a field of its struct and one line here.
//
// Pure: no clock, no I/O.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "status/json_optional.hpp"

namespace unima::status {

enum class MetricType { counter, gauge, summary };

/// Prometheus' word for the type ("counter", "gauge", "summary").
const char* type_name(MetricType type);

/// A sample's labels, name="value", in the order written.
using Labels = std::vector<std::pair<std::string, std::string>>;

struct Sample {
  nlohmann::json value;  // a number or a Boolean (1 or 0); null: left out
  Labels labels;
  const char* suffix = "";  // a summary's "_sum" or "_count"
};

/// What one statistic reads out of its part of the status.
class Samples {
 public:
  /// `value`: a number, a Boolean or an optional of one; none (null) is left out.
  template <class T>
  Samples& add(const T& value, Labels labels = {}, const char* suffix = "") {
    items_.push_back({nlohmann::json(value), std::move(labels), suffix});
    return *this;
  }
  const std::vector<Sample>& items() const { return items_; }

 private:
  std::vector<Sample> items_;
};

/// One family of /metrics, read from a part of type `Part`.
template <class Part>
struct Statistic {
  const char* name;  // after "unima_bridge_"
  MetricType type;
  const char* help;
  void (*samples)(const Part&, Samples&);
};

/// A time of the status document ("2026-11-27T10:35:19.501234Z") as Prometheus keeps
/// times, Unix seconds; none or unreadable: null, and the sample is left out.
std::optional<double> unix_seconds(const std::optional<std::string>& time);

}  // namespace unima::status
