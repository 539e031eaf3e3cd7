// report (SPEC §21): the deadbands and intervals of MQTT documents and Sparkplug DDATA.
// What a deadband's key names is checked here as far as the config knows it (a bank the
// config has); whether that bank has the value is the value model's to say
// (report/deadbands), at the same file:line:column.

#include <fmt/format.h>

#include "config/section_parsers.hpp"

namespace unima::config::sections {

namespace {

// "D1.engine_speed" -> D1 and "engine_speed"; bank A's values are named by their source,
// so "A.D1.oil_temperature" -> A and "D1.oil_temperature".
DeadbandConfig parse_deadband_key(const ParseState& state, const YAML::Node& key) {
  const auto& yaml = state.yaml;
  const auto written = yaml.text(key);
  const auto dot = written.find('.');
  const auto bank = dot == std::string::npos ? std::nullopt : banks::parse_bank_name(written.substr(0, dot));
  if (!bank || dot + 1 == written.size())
    yaml.fail(key, fmt::format("report.deadband.{}: a deadband is named `default` or <bank>.<value>, e.g. D1.engine_speed",
                               written));
  if (banks::is_write_bank(*bank))
    yaml.fail(key, fmt::format("report.deadband.{}: {} is not reported (W and X are setpoints)", written,
                               banks::bank_name(*bank)));
  if (state.shapes[banks::index_of(*bank)].length == 0)
    yaml.fail(key, fmt::format("report.deadband.{}: {} is not in this config{}", written, banks::bank_name(*bank),
                               banks::is_device_bank(*bank) ? " (no device under devices)" : ""));
  return {*bank, written.substr(dot + 1), 0, yaml.position(key)};
}

double parse_deadband(const YamlReader& yaml, const YAML::Node& node, std::string_view key) {
  const auto deadband = yaml.decimal(node);
  if (deadband < 0) yaml.fail(node, fmt::format("report.deadband.{} must be 0 or more (in the value's unit)", key));
  return deadband;
}

}  // namespace

void parse_report(ParseState& state, const YAML::Node& node) {
  const auto& yaml = state.yaml;
  yaml.expect_keys(node, "report", {"min_interval", "max_interval", "deadband"});
  auto& r = state.config.report;
  r.origin = yaml.position(node);
  if (node["min_interval"]) r.min_interval = yaml.duration(node["min_interval"]);
  if (node["max_interval"]) {
    r.max_interval = yaml.duration(node["max_interval"]);
    if (*r.max_interval <= Duration::zero()) yaml.fail(node["max_interval"], "report.max_interval must be more than 0");
  }
  const auto max = max_report_interval(state.config);
  if (r.min_interval > max)
    yaml.fail(node["min_interval"] ? node["min_interval"] : node["max_interval"],
              fmt::format("report.min_interval ({} ms) is longer than report.max_interval ({} ms{}): a full document "
                          "could never go when it must",
                          r.min_interval.count(), max.count(), r.max_interval ? "" : ", mqtt.publish.period"));
  const auto deadband = node["deadband"];
  if (!deadband) return;
  if (!deadband.IsMap()) yaml.fail(deadband, "report.deadband must be a mapping, e.g. { default: 0, D1.engine_speed: 5 }");
  for (const auto& entry : deadband) {
    const auto key = yaml.text(entry.first);
    if (key == "default") {
      r.default_deadband = parse_deadband(yaml, entry.second, key);
      continue;
    }
    auto d = parse_deadband_key(state, entry.first);
    d.deadband = parse_deadband(yaml, entry.second, key);
    r.deadbands.push_back(std::move(d));
  }
}

}  // namespace unima::config::sections
