#include "sparkplug/value_metrics.hpp"

#include <algorithm>
#include <cmath>

#include "report/change_rule.hpp"
#include "sparkplug/metric_value.hpp"

namespace unima::sparkplug {

namespace {

using values::Decoding;
using values::ValueDef;
using values::ValueType;

// The reading in the field its datatype takes; a number reaches an integer type only
// from a scale of 1, so rounding it is exact.
MetricValue value_of(DataType type, const values::Reading& reading) {
  if (const auto* number = std::get_if<double>(&reading)) {
    if (type == DataType::Float) return static_cast<float>(*number);
    if (type == DataType::Double) return *number;
    return integer_value(type, std::llround(*number));
  }
  if (const auto* flag = std::get_if<bool>(&reading)) return *flag;
  if (const auto* text = std::get_if<std::string>(&reading)) return *text;
  return std::monostate{};
}

Metric metric_of(const ValueDef& def, const values::Value& value, std::uint64_t timestamp_ms) {
  Metric metric;
  metric.name = def.name;
  metric.timestamp = timestamp_ms;
  metric.datatype = data_type_of(def);
  metric.value = value_of(*metric.datatype, value.reading);
  if (std::holds_alternative<std::monostate>(metric.value)) metric.is_null = true;
  return metric;
}

PropertySet unit_property(const std::string& unit) {
  PropertyValue text;
  text.type = DataType::String;
  text.value = unit;
  return PropertySet{{"engUnit"}, {std::move(text)}};
}

}  // namespace

DataType data_type_of(const ValueDef& def) {
  if (def.type == ValueType::boolean) return DataType::Boolean;
  if (def.type == ValueType::text) return DataType::String;
  if (def.decoding == Decoding::pair32) return def.scale == 1.0 ? DataType::UInt64 : DataType::Double;
  if (def.scale != 1.0) return DataType::Float;
  if (def.decoding == Decoding::byte_field) return DataType::UInt8;
  return def.is_signed ? DataType::Int16 : DataType::UInt16;
}

bool has_metric(const ValueDef& def) {
  const bool mapped = def.decoding == Decoding::mapped || def.decoding == Decoding::mapped_bit;
  return !mapped || def.source.has_value();
}

std::vector<Metric> metrics_of(const values::BankValues& layout, std::span<const values::Value> values,
                               std::uint64_t timestamp_ms) {
  std::vector<Metric> metrics;
  for (std::size_t i = 0; i < layout.values.size() && i < values.size(); ++i) {
    const auto& def = layout.values[i];
    if (!has_metric(def)) continue;
    auto& metric = metrics.emplace_back(metric_of(def, values[i], timestamp_ms));
    if (!def.unit.empty()) metric.properties = unit_property(def.unit);
  }
  return metrics;
}

std::vector<std::size_t> changed_values(const values::BankValues& layout, std::span<const values::Value> sent,
                                        std::span<const values::Value> values, std::span<const double> deadbands,
                                        std::span<const std::size_t> also) {
  std::vector<std::size_t> changed;
  for (std::size_t i = 0; i < layout.values.size() && i < values.size(); ++i) {
    if (!has_metric(layout.values[i])) continue;
    const bool moved = i >= sent.size() ||
                       report::counts_as_changed(sent[i], values[i], i < deadbands.size() ? deadbands[i] : 0);
    if (moved || std::find(also.begin(), also.end(), i) != also.end()) changed.push_back(i);
  }
  return changed;
}

std::vector<Metric> metrics_at(const values::BankValues& layout, std::span<const values::Value> values,
                               std::span<const std::size_t> indices, std::uint64_t timestamp_ms) {
  std::vector<Metric> metrics;
  metrics.reserve(indices.size());
  for (const auto i : indices) metrics.push_back(metric_of(layout.values[i], values[i], timestamp_ms));
  return metrics;
}

std::vector<Metric> changed_metrics_of(const values::BankValues& layout, std::span<const values::Value> sent,
                                       std::span<const values::Value> values, std::uint64_t timestamp_ms,
                                       std::span<const std::size_t> also) {
  return metrics_at(layout, values, changed_values(layout, sent, values, {}, also), timestamp_ms);
}

}  // namespace unima::sparkplug
