#pragma once
// What a metric's value field holds for its data type (Sparkplug 3.0 §6.4.17, "Datatype
// Details"): Int8, Int16, Int32, UInt8, UInt16 and UInt32 in uint32 int_value; Int64, UInt64
// and DateTime in uint64 long_value; Float, Double, Boolean, String and Text in their own.
//
// The specification gives a signed type a protobuf unsigned field and says no more (its
// issue #453 asks how). We write the two's complement sign-extended to the field's width,
// as Eclipse Tahu's Java encoder does (an Int16 -87 is int_value 0xFFFFFFA9); we read that,
// the two's complement of the type's own width (0xFFA9), and a UInt32 in long_value (what
// Ignition and Tahu sent before the specification's issue #102 was settled), since a host
// may send any of them in an NCMD or DCMD.

#include <cstdint>
#include <optional>

#include "sparkplug/payload.hpp"

namespace unima::sparkplug {

/// Int8 … UInt64 and DateTime.
bool is_integer(DataType type);
/// The integers, Float and Double.
bool is_number(DataType type);

/// `value` in the field and form `type` takes (an integer type; `value` within it).
MetricValue integer_value(DataType type, std::int64_t value);

/// The number a value holds as `type` (the metric's datatype, or the one its birth gave
/// when a command leaves it out): nullopt for a null value, a type that is no number, a
/// field that is not the type's, or an integer outside the type's range. A float is the
/// decimal it was written as (12.3f is 12.3, not 12.300000190734863).
std::optional<double> number_of(const MetricValue& value, DataType type);

/// The value of a Boolean: nullopt for a null value, another type or another field.
std::optional<bool> boolean_of(const MetricValue& value, DataType type);

}  // namespace unima::sparkplug
