#pragma once
// What the bridge publishes of each bank on MQTT (SPEC §12, §17): `<prefix>/<bank>`, a
// JSON object of the bank's values (values/value_model.hpp) by their names, flat — a
// 32-bit pair as one key ("operating_hours"), a byte pair and a bit word's bits as dotted
// keys ("knock_rank_1.level", "status.state"), A and B by their mapping sources
// ("D1.oil_temperature") — with `null` for a value not measured or of an off-line device,
// and "online" and "time" — when its newest value was measured (SPEC §21), so a document
// sent again without a new telegram says how old its values are. Unmapped entries and
// reserves are left out. A number keeps its JSON type from document to document (an
// integer, or with a fraction part when scaled: 85.0, values/value_json), which a
// historian with a fixed field type needs. When a bank is due is report::ReportSchedule's
// to say. Pure: values and times are passed in.

#include <chrono>
#include <span>
#include <vector>

#include <nlohmann/json.hpp>

#include "values/value_model.hpp"

namespace unima::mqtt {

/// The banks published of a value model: A, B, C, D1..D4, S1..S7 (not W or X), in the
/// model's order.
std::vector<banks::BankId> published_banks(const values::ValueModel& model);

/// The document: "time" (`measured`: report::MeasurementTimes), "online", then the values
/// in the table's order.
nlohmann::ordered_json bank_document(const values::BankValues& layout, std::span<const values::Value> values, bool online,
                                     std::chrono::system_clock::time_point measured);

}  // namespace unima::mqtt
