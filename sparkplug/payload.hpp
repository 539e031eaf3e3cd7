#pragma once
// The Sparkplug B payload (SPEC §16) as plain values: what sparkplug/payload_codec.hpp puts
// on the wire and reads back. The messages and their fields are those of the Eclipse
// Sparkplug 3.0.0 specification, chapter 6 "Payloads" (§6.4 "Sparkplug B MQTT Payload
// Definition": the protobuf schema, §6.4.2–§6.4.9 the components, §6.4.16–§6.4.17 the data
// types), checked field by field against the specification's text
// (eclipse-sparkplug/sparkplug, specification/.../chapters/Sparkplug_6_Payloads.adoc).
// Every field of Payload, Metric, PropertySet and PropertyValue is here; the parts nothing
// in the bridge reads or writes (a metric's MetaData, a DataSet, a Template, the extension
// values) are kept as their encoded bytes, so that what is decoded encodes back the same.
// Extensions past the schema's fields ("extensions 6 to max") are unknown fields to us.
//
// proto2: a field that is absent differs from one that holds its default, so every
// optional field is a std::optional here.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace unima::sparkplug {

/// Sparkplug's data types, by their numbers in the specification's `DataType` enum
/// (§6.4.16). The numbering is the protocol's: a host names a metric's type by it.
enum class DataType : std::uint32_t {
  Unknown = 0,
  Int8 = 1,
  Int16 = 2,
  Int32 = 3,
  Int64 = 4,
  UInt8 = 5,
  UInt16 = 6,
  UInt32 = 7,
  UInt64 = 8,
  Float = 9,
  Double = 10,
  Boolean = 11,
  String = 12,
  DateTime = 13,
  Text = 14,
  UUID = 15,
  DataSet = 16,
  Bytes = 17,
  File = 18,
  Template = 19,
  PropertySet = 20,
  PropertySetList = 21,
  Int8Array = 22,
  Int16Array = 23,
  Int32Array = 24,
  Int64Array = 25,
  UInt8Array = 26,
  UInt16Array = 27,
  UInt32Array = 28,
  UInt64Array = 29,
  FloatArray = 30,
  DoubleArray = 31,
  BooleanArray = 32,
  StringArray = 33,
  DateTimeArray = 34,
};

/// "Int16", "Boolean", ...: the specification's name; "DataType(99)" for a number it does
/// not define (a host may send one).
std::string data_type_name(DataType type);

/// A protobuf `bytes` field, apart from `string` so that the two value fields stay apart.
struct Bytes {
  std::string data;
  bool operator==(const Bytes&) const = default;
};

/// A value field the bridge neither makes nor reads (a DataSet, a Template, an extension
/// value): its number (Metric: 17, 18 or 19; PropertyValue: 11) and its encoded message,
/// carried through unchanged.
struct EncodedMessage {
  std::uint32_t field = 0;
  std::string bytes;
  bool operator==(const EncodedMessage&) const = default;
};

struct PropertyValue;

/// Payload.PropertySet (§6.4.6): keys and values, two arrays the specification requires to
/// be of one length. The decoder keeps what came, so a host's set of unequal arrays is
/// seen as such (`well_formed`).
struct PropertySet {
  std::vector<std::string> keys;          // field 1
  std::vector<PropertyValue> values;      // field 2

  bool well_formed() const;
  /// The value of `key`; nullptr when there is none (or the arrays differ in length there).
  const PropertyValue* find(std::string_view key) const;
  bool operator==(const PropertySet&) const;
};

/// Payload.PropertySetList (§6.4.8).
struct PropertySetList {
  std::vector<PropertySet> propertysets;   // field 1
  bool operator==(const PropertySetList&) const;
};

/// Payload.PropertyValue (§6.4.7): type = 1, is_null = 2, and `oneof value` int_value = 3,
/// long_value = 4, float_value = 5, double_value = 6, boolean_value = 7, string_value = 8,
/// propertyset_value = 9, propertysets_value = 10, extension_value = 11. The alternative's
/// type says which field holds the value; a signed type is held as its two's complement
/// (sparkplug/metric_value.hpp writes and reads them).
struct PropertyValue {
  using Value = std::variant<std::monostate, std::uint32_t, std::uint64_t, float, double, bool, std::string, PropertySet,
                             PropertySetList, EncodedMessage>;
  std::optional<DataType> type;
  std::optional<bool> is_null;
  Value value;
  bool operator==(const PropertyValue&) const = default;
};

/// Metric's `oneof value` (§6.4.3): int_value = 10 (uint32), long_value = 11 (uint64),
/// float_value = 12, double_value = 13, boolean_value = 14, string_value = 15, bytes_value
/// = 16, and dataset_value = 17, template_value = 18, extension_value = 19 as
/// EncodedMessage. monostate: none (a null metric may leave it out, §6.4.3 "value").
using MetricValue =
    std::variant<std::monostate, std::uint32_t, std::uint64_t, float, double, bool, std::string, Bytes, EncodedMessage>;

/// Payload.Metric (§6.4.3): name = 1, alias = 2, timestamp = 3, datatype = 4,
/// is_historical = 5, is_transient = 6, is_null = 7, metadata = 8, properties = 9, value.
struct Metric {
  std::optional<std::string> name;
  std::optional<std::uint64_t> alias;
  std::optional<std::uint64_t> timestamp;  // ms since the epoch, UTC
  std::optional<DataType> datatype;        // uint32 on the wire; any number a host sends is kept
  std::optional<bool> is_historical;
  std::optional<bool> is_transient;
  std::optional<bool> is_null;
  std::optional<Bytes> metadata;           // Payload.MetaData, encoded, as it came
  std::optional<PropertySet> properties;
  MetricValue value;
  bool operator==(const Metric&) const = default;
};

/// Payload (§6.4.2): timestamp = 1, metrics = 2, seq = 3, uuid = 4, body = 5. Its
/// extensions (6 and up), like any field the schema does not name, are skipped when read.
struct Payload {
  std::optional<std::uint64_t> timestamp;  // ms since the epoch, UTC: when it was published
  std::vector<Metric> metrics;
  std::optional<std::uint64_t> seq;        // 0–255 (§6.4.2); the session counts it
  std::optional<std::string> uuid;
  std::optional<Bytes> body;
  bool operator==(const Payload&) const = default;
};

}  // namespace unima::sparkplug
