// sparkplug/payload_codec (SPEC §16): the Sparkplug B payload to bytes and back. The
// expected bytes are derived by hand from protobuf's encoding rules (tag = field << 3 |
// wire type; varints seven bits at a time, low first; fixed32/64 little-endian) and the
// field numbers of the Sparkplug 3.0 specification (§6.4); the comments show the sums.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "sparkplug/metric_value.hpp"
#include "sparkplug/payload_codec.hpp"

namespace unima::sparkplug {
namespace {

std::vector<std::uint8_t> hex(std::string_view text) {
  std::vector<std::uint8_t> bytes;
  std::string digits;
  for (const char c : text)
    if (c != ' ') digits += c;
  for (std::size_t i = 0; i + 1 < digits.size(); i += 2)
    bytes.push_back(static_cast<std::uint8_t>(std::stoul(digits.substr(i, 2), nullptr, 16)));
  return bytes;
}

Payload decoded(const std::vector<std::uint8_t>& bytes) {
  auto result = decode_payload(bytes);
  EXPECT_TRUE(result.payload.has_value()) << (result.error ? describe(*result.error) : "");
  EXPECT_FALSE(result.error.has_value());
  return result.payload.value_or(Payload{});
}

DecodeError refused(const std::vector<std::uint8_t>& bytes) {
  auto result = decode_payload(bytes);
  EXPECT_FALSE(result.payload.has_value());
  EXPECT_TRUE(result.error.has_value());
  return result.error.value_or(DecodeError{});
}

Metric named(std::string name, DataType type, MetricValue value) {
  Metric m;
  m.name = std::move(name);
  m.datatype = type;
  m.value = std::move(value);
  return m;
}

TEST(SparkplugCodec, AnEmptyPayloadIsNoBytes) {
  EXPECT_TRUE(encode_payload(Payload{}).empty());
  EXPECT_EQ(decoded({}), Payload{});
}

TEST(SparkplugCodec, PayloadFieldsAreVarintsAndStringsInFieldOrder) {
  Payload p;
  p.timestamp = 300;  // 300 = 0b10'0101100: 0xAC (low 7 bits | more), 0x02
  p.seq = 0;          // a present zero is written: proto2 optional (NBIRTH's seq is 0)
  p.uuid = "u";
  p.body = Bytes{"\x01\x02"};
  const auto expected = hex("08 AC 02"     // field 1 varint: 1<<3|0
                            "18 00"        // field 3 varint: 3<<3|0
                            "22 01 75"     // field 4 length-delimited: 4<<3|2, 1 byte, 'u'
                            "2A 02 01 02"  // field 5 length-delimited: 5<<3|2
  );
  EXPECT_EQ(encode_payload(p), expected);
  EXPECT_EQ(decoded(expected), p);
}

TEST(SparkplugCodec, ABooleanMetric) {
  Payload p;
  p.metrics.push_back(named("b", DataType::Boolean, true));
  // Metric: name 0A 01 'b'; datatype 20 0B (4<<3|0, Boolean = 11); boolean_value 70 01
  // (14<<3|0 = 112). The Payload holds it as field 2 (2<<3|2 = 0x12), 7 bytes long.
  const auto expected = hex("12 07 0A 01 62 20 0B 70 01");
  EXPECT_EQ(encode_payload(p), expected);
  EXPECT_EQ(decoded(expected), p);
}

TEST(SparkplugCodec, ANegativeInt16IsItsTwosComplementSignExtendedInIntValue) {
  Payload p;
  p.metrics.push_back(named("a", DataType::Int16, integer_value(DataType::Int16, -87)));
  // -87 as a 32-bit two's complement is 0xFFFFFFA9: varint A9 FF FF FF 0F (no zig-zag:
  // int_value is a uint32). int_value is field 10 varint: 10<<3|0 = 0x50.
  const auto expected = hex("12 0B 0A 01 61 20 02 50 A9 FF FF FF 0F");
  EXPECT_EQ(encode_payload(p), expected);
  const auto back = decoded(expected);
  ASSERT_EQ(back.metrics.size(), 1u);
  EXPECT_EQ(number_of(back.metrics[0].value, DataType::Int16), -87.0);
}

TEST(SparkplugCodec, FloatAndDoubleAreLittleEndianFixedFields) {
  Payload p;
  p.metrics.push_back(named("f", DataType::Float, 21.5f));  // 0x41AC0000
  p.metrics.push_back(named("d", DataType::Double, 1.5));   // 0x3FF8000000000000
  const auto expected = hex("12 0A 0A 01 66 20 09 65 00 00 AC 41"                 // float_value: 12<<3|5 = 0x65
                            "12 0E 0A 01 64 20 0A 69 00 00 00 00 00 00 F8 3F"  // double_value: 13<<3|1 = 0x69
  );
  EXPECT_EQ(encode_payload(p), expected);
  EXPECT_EQ(decoded(expected), p);
}

TEST(SparkplugCodec, ANullMetricWithItsUnitAsAPropertySet) {
  Metric m;
  m.name = "t";
  m.timestamp = 5;
  m.datatype = DataType::Int16;
  m.is_null = true;
  PropertyValue unit;
  unit.type = DataType::String;
  unit.value = std::string("\xC2\xB0" "C");  // "°C" in UTF-8
  m.properties = PropertySet{{"engUnit"}, {unit}};
  Payload p;
  p.metrics.push_back(m);
  // PropertyValue: type 08 0C (String = 12), string_value 42 03 C2 B0 43 (8<<3|2): 7 bytes.
  // PropertySet: key 0A 07 "engUnit", value 12 07 <PropertyValue>: 18 bytes.
  // Metric: name 0A 01 't', timestamp 18 05, datatype 20 02, is_null 38 01, properties
  // 4A 12 <PropertySet>, no value field: 29 bytes.
  const auto expected = hex("12 1D 0A 01 74 18 05 20 02 38 01 4A 12"
                            "0A 07 65 6E 67 55 6E 69 74"
                            "12 07 08 0C 42 03 C2 B0 43");
  EXPECT_EQ(encode_payload(p), expected);
  const auto back = decoded(expected);
  EXPECT_EQ(back, p);
  ASSERT_TRUE(back.metrics[0].properties.has_value());
  const auto* found = back.metrics[0].properties->find("engUnit");
  ASSERT_NE(found, nullptr);
  EXPECT_EQ(std::get<std::string>(found->value), "\xC2\xB0" "C");
}

TEST(SparkplugCodec, TheSpecificationsExamplePayload) {
  // Sparkplug 3.0 §6.4.1: {"timestamp": 1486144502122, "metrics": [{"name": "My Metric",
  // "alias": 1, "timestamp": 1479123452194, "dataType": "String", "value": "Test"}], "seq": 2}
  Payload p;
  p.timestamp = 1486144502122;
  p.seq = 2;
  Metric m = named("My Metric", DataType::String, std::string("Test"));
  m.alias = 1;
  m.timestamp = 1479123452194;
  p.metrics.push_back(m);
  // 1486144502122 = 0x15A051D796A, seven bits at a time from the low end, each but the
  // last with 0x80: 6A|80, 72|80, 75|80, 28|80, 20|80, 2B.
  const auto expected = hex("08 EA F2 F5 A8 A0 2B"
                            "12 1C 0A 09 4D 79 20 4D 65 74 72 69 63"  // 28 bytes; name "My Metric"
                            "10 01"                                   // alias (2<<3|0)
                            "18 A2 82 83 95 86 2B"                    // timestamp 1479123452194
                            "20 0C"                                   // datatype String
                            "7A 04 54 65 73 74"                       // string_value (15<<3|2 = 0x7A) "Test"
                            "18 02");                                 // seq
  EXPECT_EQ(encode_payload(p), expected);
  EXPECT_EQ(decoded(expected), p);
}

TEST(SparkplugCodec, EveryDataTypeTheBridgeUsesRoundTrips) {
  Payload p;
  p.timestamp = 1700000000000;
  p.seq = 255;
  p.metrics.push_back(named("i8", DataType::Int8, integer_value(DataType::Int8, -128)));
  p.metrics.push_back(named("i16", DataType::Int16, integer_value(DataType::Int16, -32768)));
  p.metrics.push_back(named("i32", DataType::Int32, integer_value(DataType::Int32, std::numeric_limits<std::int32_t>::min())));
  p.metrics.push_back(named("i64", DataType::Int64, integer_value(DataType::Int64, std::numeric_limits<std::int64_t>::min())));
  p.metrics.push_back(named("u8", DataType::UInt8, integer_value(DataType::UInt8, 255)));
  p.metrics.push_back(named("u16", DataType::UInt16, integer_value(DataType::UInt16, 65535)));
  p.metrics.push_back(named("u32", DataType::UInt32, integer_value(DataType::UInt32, 4294967295)));
  p.metrics.push_back(named("u64", DataType::UInt64, std::numeric_limits<std::uint64_t>::max()));
  p.metrics.push_back(named("float", DataType::Float, -0.78125f));
  p.metrics.push_back(named("double", DataType::Double, 429496729.5));
  p.metrics.push_back(named("bool", DataType::Boolean, false));
  p.metrics.push_back(named("string", DataType::String, std::string("ab")));
  p.metrics.push_back(named("text", DataType::Text, std::string("")));
  p.metrics.push_back(named("datetime", DataType::DateTime, std::uint64_t{1700000000000}));
  p.metrics.push_back(named("bytes", DataType::Bytes, Bytes{std::string("\0\xFF", 2)}));
  Metric flags = named("flags", DataType::UInt16, integer_value(DataType::UInt16, 0));
  flags.is_historical = false;
  flags.is_transient = true;
  flags.alias = 18446744073709551615u;  // the ten-byte varint
  p.metrics.push_back(flags);
  const auto back = decoded(encode_payload(p));
  EXPECT_EQ(back, p);
  const std::vector<std::pair<std::size_t, double>> numbers = {
      {0, -128}, {1, -32768}, {2, -2147483648.0}, {3, -9223372036854775808.0}, {4, 255}, {5, 65535}, {6, 4294967295.0}};
  for (const auto& [index, number] : numbers)
    EXPECT_EQ(number_of(back.metrics[index].value, *back.metrics[index].datatype), number) << *back.metrics[index].name;
}

TEST(SparkplugCodec, NestedPropertySetsListsAndKeptMessagesRoundTrip) {
  PropertyValue inner;
  inner.type = DataType::Int32;
  inner.value = std::uint32_t{192};
  PropertySet leaf{{"Quality"}, {inner}};
  PropertyValue set_value;
  set_value.type = DataType::PropertySet;
  set_value.value = leaf;
  PropertyValue list_value;
  list_value.type = DataType::PropertySetList;
  list_value.value = PropertySetList{{leaf, PropertySet{}}};
  PropertyValue null_value;
  null_value.type = DataType::Double;
  null_value.is_null = true;
  PropertyValue others;
  others.value = EncodedMessage{11, "\x08\x01"};
  Metric m = named("nested", DataType::Template, EncodedMessage{18, std::string("\x0A\x01x", 3)});
  m.metadata = Bytes{"\x10\x01"};
  m.properties = PropertySet{{"set", "list", "null", "ext", "long", "float", "double", "bool"},
                             {set_value, list_value, null_value, others, PropertyValue{{}, {}, std::uint64_t{7}},
                              PropertyValue{{}, {}, 1.5f}, PropertyValue{{}, {}, 2.5}, PropertyValue{{}, {}, true}}};
  Payload p;
  p.metrics.push_back(m);
  p.metrics.push_back(named("dataset", DataType::DataSet, EncodedMessage{17, ""}));
  p.metrics.push_back(named("extension", DataType::Unknown, EncodedMessage{19, "\x08\x02"}));
  EXPECT_EQ(decoded(encode_payload(p)), p);
}

TEST(SparkplugCodec, UnknownFieldsAreSkippedWhateverTheirWireType) {
  const auto bytes = hex("30 05"                    // field 6 varint (a Payload extension)
                         "3A 02 AA BB"              // field 7 length-delimited
                         "3D 01 02 03 04"           // field 7 fixed32
                         "39 01 02 03 04 05 06 07 08"  // field 7 fixed64
                         "33 08 01 34"              // field 6 group holding field 1 = 1
                         "18 07"                    // seq 7
                         "12 06 0A 01 6D F8 01 00"  // a Metric with field 31 (31<<3 = 0xF8 0x01)
  );
  const auto p = decoded(bytes);
  EXPECT_EQ(p.seq, 7u);
  ASSERT_EQ(p.metrics.size(), 1u);
  EXPECT_EQ(p.metrics[0].name, "m");
}

TEST(SparkplugCodec, ProtobufsRulesForRepeatedOccurrences) {
  const auto p = decoded(hex("18 01 18 02"                                   // seq twice: the last
                             "12 1B"                                         // one Metric, 27 bytes:
                             "0A 01 61 0A 01 62"                             //   name twice: the last
                             "50 05 7A 01 78"                                //   int_value then string_value: the last
                             "4A 05 0A 01 6B 12 00"                          //   properties { "k": {} }
                             "4A 05 0A 01 6C 12 00"                          //   properties again: merged
                             "38 02"));                                      //   is_null 2: true
  EXPECT_EQ(p.seq, 2u);
  ASSERT_EQ(p.metrics.size(), 1u);
  const auto& m = p.metrics[0];
  EXPECT_EQ(m.name, "b");
  EXPECT_EQ(m.value, MetricValue(std::string("x")));
  ASSERT_TRUE(m.properties.has_value());
  EXPECT_EQ(m.properties->keys, (std::vector<std::string>{"k", "l"}));
  EXPECT_EQ(m.properties->values.size(), 2u);
  EXPECT_EQ(m.is_null, true);
}

TEST(SparkplugCodec, AUint32FieldKeepsTheLowBitsOfALongerVarint) {
  // datatype 0x1_0000_0002 (an Int16 whose sender put 64 bits): protobuf keeps the low 32.
  const auto p = decoded(hex("12 08 20 82 80 80 80 10 50 01"));
  ASSERT_EQ(p.metrics.size(), 1u);
  EXPECT_EQ(p.metrics[0].datatype, DataType::Int16);
}

TEST(SparkplugCodec, NonCanonicalVarintsAreAccepted) {
  EXPECT_EQ(decoded(hex("18 80 00")).seq, 0u);  // zero in two bytes: a valid varint
}

TEST(SparkplugCodec, AnInputThatEndsInsideAFieldIsTruncated) {
  EXPECT_EQ(refused(hex("08")), (DecodeError{DecodeProblem::truncated, 1, "Payload", 1}));
  EXPECT_EQ(refused(hex("08 80")), (DecodeError{DecodeProblem::truncated, 1, "Payload", 1}));
  EXPECT_EQ(refused(hex("80")), (DecodeError{DecodeProblem::truncated, 0, "Payload", 0}));
  EXPECT_EQ(refused(hex("12 06 0A 01 6D 65 00 00")), (DecodeError{DecodeProblem::truncated, 6, "Metric", 12}))
      << "a float needs four bytes of its message";
  EXPECT_EQ(refused(hex("12 03 0A 01 6D 39 00")).problem, DecodeProblem::truncated)
      << "an unknown fixed64 field cut short";
}

TEST(SparkplugCodec, AVarintPast64BitsIsOverlong) {
  EXPECT_EQ(refused(hex("08 FF FF FF FF FF FF FF FF FF 02")), (DecodeError{DecodeProblem::overlong_varint, 1, "Payload", 1}));
  EXPECT_EQ(refused(hex("08 80 80 80 80 80 80 80 80 80 80 00")).problem, DecodeProblem::overlong_varint);
  EXPECT_EQ(decoded(hex("08 FF FF FF FF FF FF FF FF FF 01")).timestamp, std::numeric_limits<std::uint64_t>::max());
}

TEST(SparkplugCodec, ATagOfFieldZeroOrPast32BitsIsRefused) {
  EXPECT_EQ(refused(hex("00 00")), (DecodeError{DecodeProblem::bad_tag, 0, "Payload", 0}));
  EXPECT_EQ(refused(hex("80 80 80 80 10 00")).problem, DecodeProblem::bad_tag);  // 2^32
  EXPECT_EQ(refused(hex("0E")), (DecodeError{DecodeProblem::bad_wire_type, 0, "Payload", 0}));
  EXPECT_EQ(refused(hex("0F")).problem, DecodeProblem::bad_wire_type);
}

TEST(SparkplugCodec, AKnownFieldOfAnotherWireTypeIsRefused) {
  EXPECT_EQ(refused(hex("0D 00 00 00 00")), (DecodeError{DecodeProblem::wrong_wire_type, 0, "Payload", 1}));
  EXPECT_EQ(refused(hex("10 01")), (DecodeError{DecodeProblem::wrong_wire_type, 0, "Payload", 2}))
      << "metrics as a varint";
  EXPECT_EQ(refused(hex("12 05 0A 01 6D 60 00")), (DecodeError{DecodeProblem::wrong_wire_type, 5, "Metric", 12}))
      << "a float_value as a varint";
  EXPECT_EQ(refused(hex("12 04 4A 02 10 00")), (DecodeError{DecodeProblem::wrong_wire_type, 4, "PropertySet", 2}));
  EXPECT_EQ(refused(hex("0B 0C")).problem, DecodeProblem::wrong_wire_type) << "a known field as a group";
}

TEST(SparkplugCodec, ALengthPastTheEndOfItsMessageIsRefused) {
  EXPECT_EQ(refused(hex("12 05 0A")), (DecodeError{DecodeProblem::length_past_end, 1, "Payload", 2}));
  EXPECT_EQ(refused(hex("12 03 0A 05 6D")), (DecodeError{DecodeProblem::length_past_end, 3, "Metric", 1}))
      << "the name would run past its metric";
  EXPECT_EQ(refused(hex("2A FF FF FF FF FF FF FF FF 7F")).problem, DecodeProblem::length_past_end);
}

TEST(SparkplugCodec, MessagesNestedDeeperThanTheLimitAreRefused) {
  // PropertyValue{propertyset_value: PropertySet{values: [PropertyValue{...}]}}, from the
  // innermost out: each PropertySet adds two messages.
  const auto wrap = [](std::uint8_t tag, const std::vector<std::uint8_t>& inner) {
    std::vector<std::uint8_t> out{tag};
    std::size_t length = inner.size();
    for (; length >= 0x80; length >>= 7) out.push_back(static_cast<std::uint8_t>(length | 0x80));
    out.push_back(static_cast<std::uint8_t>(length));
    for (const auto byte : inner) out.push_back(byte);
    return out;
  };
  const auto nested_payload = [&](unsigned sets) {
    std::vector<std::uint8_t> value;  // an empty PropertyValue
    for (unsigned i = 1; i < sets; ++i) value = wrap(0x4A, wrap(0x12, value));  // propertyset_value { values }
    const auto properties = wrap(0x4A, wrap(0x12, value));                       // Metric.properties { values }
    return wrap(0x12, properties);                                               // Payload.metrics
  };
  // Payload, Metric, then two per set: 2 + 2 × 15 = 32 messages pass, one more set does not.
  EXPECT_TRUE(decode_payload(nested_payload(15)).payload.has_value());
  const auto deep = refused(nested_payload(16));
  EXPECT_EQ(deep.problem, DecodeProblem::too_deep);
  EXPECT_EQ(deep.message, "PropertyValue");
  // Unknown groups count too.
  std::vector<std::uint8_t> groups(40, 0x33);
  EXPECT_EQ(refused(groups).problem, DecodeProblem::too_deep);
}

TEST(SparkplugCodec, AGroupMustEndWithItsOwnEndGroup) {
  EXPECT_EQ(refused(hex("33 08 01")), (DecodeError{DecodeProblem::unmatched_group, 0, "Payload", 1}))
      << "never closed";
  EXPECT_EQ(refused(hex("33 3C")).problem, DecodeProblem::unmatched_group) << "closed as field 7";
  EXPECT_EQ(refused(hex("34")), (DecodeError{DecodeProblem::unmatched_group, 0, "Payload", 6})) << "an end alone";
}

TEST(SparkplugCodec, ErrorsAreDescribedForALogLine) {
  EXPECT_EQ(describe(DecodeError{DecodeProblem::wrong_wire_type, 5, "Metric", 12}),
            "byte 5, Metric field 12: a wire type the schema does not give this field");
  EXPECT_EQ(describe(DecodeError{DecodeProblem::truncated, 0, "Payload", 0}), "byte 0, Payload: the input ends inside a field");
}

TEST(SparkplugCodec, FloatBitsSurviveTheRoundTrip) {
  Payload p;
  p.metrics.push_back(named("nan", DataType::Float, std::numeric_limits<float>::quiet_NaN()));
  const auto bytes = encode_payload(p);
  const auto back = decoded(bytes);
  ASSERT_EQ(back.metrics.size(), 1u);
  EXPECT_TRUE(std::isnan(std::get<float>(back.metrics[0].value)));
  EXPECT_EQ(encode_payload(back), bytes);
}

TEST(SparkplugCodec, DataTypesAreNamedAsTheSpecificationNamesThem) {
  EXPECT_EQ(data_type_name(DataType::Int16), "Int16");
  EXPECT_EQ(data_type_name(DataType::PropertySetList), "PropertySetList");
  EXPECT_EQ(data_type_name(DataType::DateTimeArray), "DateTimeArray");
  EXPECT_EQ(data_type_name(static_cast<DataType>(99)), "DataType(99)");
}

}  // namespace
}  // namespace unima::sparkplug
