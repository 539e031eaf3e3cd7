#include "sparkplug/payload.hpp"

#include <array>

namespace unima::sparkplug {

std::string data_type_name(DataType type) {
  // In the order of the specification's enum (§6.4.16), so the number is the index.
  static constexpr std::array<std::string_view, 35> names = {
      "Unknown",     "Int8",        "Int16",        "Int32",        "Int64",         "UInt8",        "UInt16",
      "UInt32",      "UInt64",      "Float",        "Double",       "Boolean",       "String",       "DateTime",
      "Text",        "UUID",        "DataSet",      "Bytes",        "File",          "Template",     "PropertySet",
      "PropertySetList", "Int8Array", "Int16Array", "Int32Array",   "Int64Array",    "UInt8Array",   "UInt16Array",
      "UInt32Array", "UInt64Array", "FloatArray",   "DoubleArray",  "BooleanArray",  "StringArray",  "DateTimeArray"};
  const auto number = static_cast<std::uint32_t>(type);
  if (number < names.size()) return std::string(names[number]);
  return "DataType(" + std::to_string(number) + ")";
}

bool PropertySet::well_formed() const { return keys.size() == values.size(); }

const PropertyValue* PropertySet::find(std::string_view key) const {
  for (std::size_t i = 0; i < keys.size() && i < values.size(); ++i)
    if (keys[i] == key) return &values[i];
  return nullptr;
}

bool PropertySet::operator==(const PropertySet& other) const { return keys == other.keys && values == other.values; }

bool PropertySetList::operator==(const PropertySetList& other) const { return propertysets == other.propertysets; }

}  // namespace unima::sparkplug
