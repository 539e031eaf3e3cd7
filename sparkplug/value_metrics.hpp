#pragma once
// The value model's values as Sparkplug metrics (SPEC §16, §17): a bank's DBIRTH carries a
// metric per value, a DDATA the values that changed. The values are those of
// values::ValueModel, the one decoding of the registers the page and MQTT read too; only
// how each is typed and put is decided here:
//
//   value (values::ValueDef)                    metric datatype (its value field)
//   a bit, a mapped bit (B, C's user bits),      Boolean
//   a bit of X (x.0 … x.15)
//   an ASCII pair                                String
//   a 32-bit pair, scale 1                       UInt64  (long_value: a UInt32 in int_value,
//                                                        as the specification puts it, is
//                                                        null to Eclipse Tahu's JS codec,
//                                                        which reads long_value — Tahu #397)
//   a 32-bit pair, scaled                        Double  (a Float's 24 bits would round
//                                                        operating hours past 16.7 million)
//   any other number with a scale other than 1   Float   (16 bits of raw × scale fit it)
//   a byte of a byte pair, scale 1               UInt8
//   a signed register, scale 1                   Int16   (two's complement, sparkplug/metric_value.hpp)
//   an unsigned register, a bit word (X's `x`),  UInt16
//   a field of several bits
//
// Each metric is named by the value's name (the table's identifier: "engine_speed",
// "operating_hours", "knock_rank_1.level", "status_word.alarm"; bank A's by its source,
// "D1.oil_temperature"), carries the value's unit as the String property `engUnit` in its
// birth, and a value with no reading (not measured, off-line, never written) is
// is_null = true with its datatype still set. A value that is not mapped (an entry of A or
// B without a source) is left out: the birth names every metric a bank will ever carry,
// so a W or X never written is in it, null, and a later write sends its value.

#include <cstdint>
#include <span>
#include <vector>

#include "sparkplug/payload.hpp"
#include "values/value_model.hpp"

namespace unima::sparkplug {

/// The datatype of `def`'s metric (the table above).
DataType data_type_of(const values::ValueDef& def);

/// Whether a value is a metric at all: not an entry of A or B without a source.
bool has_metric(const values::ValueDef& def);

/// The metrics of a bank's DBIRTH: one per value that has a metric, in the bank's order,
/// each with name, `timestamp_ms` (ms since the epoch, UTC), datatype, its reading or
/// is_null, and `engUnit` when the value has a unit. `values` are
/// values::ValueModel::evaluate's for `layout`.
std::vector<Metric> metrics_of(const values::BankValues& layout, std::span<const values::Value> values,
                               std::uint64_t timestamp_ms);

/// The values of a DDATA, by their index in the layout: those with a metric that count as
/// changed (report/change_rule, by `deadbands`: report::Deadbands::of, empty: 0 for all)
/// from `sent` (what the bank's last birth or data message carried of each); none when
/// nothing changed. A value that only changed why it is null (not measured to off-line)
/// is no change on Sparkplug. The values at `also` are sent changed or not: a host told
/// again what a refused command left as it was.
std::vector<std::size_t> changed_values(const values::BankValues& layout, std::span<const values::Value> sent,
                                        std::span<const values::Value> values, std::span<const double> deadbands,
                                        std::span<const std::size_t> also = {});

/// The metrics of the values at `indices`, with name, timestamp, datatype and reading or is_null.
std::vector<Metric> metrics_at(const values::BankValues& layout, std::span<const values::Value> values,
                               std::span<const std::size_t> indices, std::uint64_t timestamp_ms);

/// metrics_at(changed_values()) without deadbands: every change counts.
std::vector<Metric> changed_metrics_of(const values::BankValues& layout, std::span<const values::Value> sent,
                                       std::span<const values::Value> values, std::uint64_t timestamp_ms,
                                       std::span<const std::size_t> also = {});

}  // namespace unima::sparkplug
