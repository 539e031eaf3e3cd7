// encode_payload: the messages of sparkplug/payload.hpp in protobuf's wire format, each
// field in number order (sparkplug/payload_codec.hpp says why our own).

#include <bit>

#include "sparkplug/payload_codec.hpp"
#include "sparkplug/wire_type.hpp"

namespace unima::sparkplug {

namespace {

using Buffer = std::vector<std::uint8_t>;

void put_varint(Buffer& out, std::uint64_t value) {
  while (value >= 0x80) {
    out.push_back(static_cast<std::uint8_t>(value | 0x80));
    value >>= 7;
  }
  out.push_back(static_cast<std::uint8_t>(value));
}

void put_tag(Buffer& out, std::uint32_t field, WireType type) {
  put_varint(out, std::uint64_t{field} << 3 | static_cast<std::uint8_t>(type));
}

void put_varint_field(Buffer& out, std::uint32_t field, std::uint64_t value) {
  put_tag(out, field, WireType::varint);
  put_varint(out, value);
}

void put_fixed(Buffer& out, std::uint64_t bits, unsigned bytes) {
  for (unsigned i = 0; i < bytes; ++i) out.push_back(static_cast<std::uint8_t>(bits >> (8 * i)));  // little-endian
}

void put_float_field(Buffer& out, std::uint32_t field, float value) {
  put_tag(out, field, WireType::fixed32);
  put_fixed(out, std::bit_cast<std::uint32_t>(value), 4);
}

void put_double_field(Buffer& out, std::uint32_t field, double value) {
  put_tag(out, field, WireType::fixed64);
  put_fixed(out, std::bit_cast<std::uint64_t>(value), 8);
}

void put_bytes_field(Buffer& out, std::uint32_t field, std::string_view bytes) {
  put_tag(out, field, WireType::length_delimited);
  put_varint(out, bytes.size());
  out.insert(out.end(), bytes.begin(), bytes.end());
}

void put_message_field(Buffer& out, std::uint32_t field, const Buffer& message) {
  put_tag(out, field, WireType::length_delimited);
  put_varint(out, message.size());
  out.insert(out.end(), message.begin(), message.end());
}

template <typename T>
void put_optional_varint(Buffer& out, std::uint32_t field, const std::optional<T>& value) {
  if (value) put_varint_field(out, field, static_cast<std::uint64_t>(*value));
}

// The scalar alternatives shared by Metric's and PropertyValue's `oneof value`, numbered
// from the field of int_value (Metric 10, PropertyValue 3): int, long, float, double,
// boolean and string follow it in both.
struct ScalarFields {
  Buffer& out;
  std::uint32_t int_field;
  void operator()(std::monostate) const {}
  void operator()(std::uint32_t v) const { put_varint_field(out, int_field, v); }
  void operator()(std::uint64_t v) const { put_varint_field(out, int_field + 1, v); }
  void operator()(float v) const { put_float_field(out, int_field + 2, v); }
  void operator()(double v) const { put_double_field(out, int_field + 3, v); }
  void operator()(bool v) const { put_varint_field(out, int_field + 4, v ? 1 : 0); }
  void operator()(const std::string& v) const { put_bytes_field(out, int_field + 5, v); }
  void operator()(const EncodedMessage& v) const { put_bytes_field(out, v.field, v.bytes); }
};

Buffer property_set(const PropertySet& set);

Buffer property_set_list(const PropertySetList& list) {
  Buffer out;
  for (const auto& set : list.propertysets) put_message_field(out, 1, property_set(set));
  return out;
}

Buffer property_value(const PropertyValue& value) {
  Buffer out;
  put_optional_varint(out, 1, value.type);
  put_optional_varint(out, 2, value.is_null);
  const ScalarFields scalar{out, 3};
  std::visit(
      [&](const auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, PropertySet>)
          put_message_field(out, 9, property_set(v));
        else if constexpr (std::is_same_v<T, PropertySetList>)
          put_message_field(out, 10, property_set_list(v));
        else
          scalar(v);
      },
      value.value);
  return out;
}

Buffer property_set(const PropertySet& set) {
  Buffer out;
  for (const auto& key : set.keys) put_bytes_field(out, 1, key);
  for (const auto& value : set.values) put_message_field(out, 2, property_value(value));
  return out;
}

Buffer metric(const Metric& m) {
  Buffer out;
  if (m.name) put_bytes_field(out, 1, *m.name);
  put_optional_varint(out, 2, m.alias);
  put_optional_varint(out, 3, m.timestamp);
  put_optional_varint(out, 4, m.datatype);
  put_optional_varint(out, 5, m.is_historical);
  put_optional_varint(out, 6, m.is_transient);
  put_optional_varint(out, 7, m.is_null);
  if (m.metadata) put_bytes_field(out, 8, m.metadata->data);
  if (m.properties) put_message_field(out, 9, property_set(*m.properties));
  const ScalarFields scalar{out, 10};
  std::visit(
      [&](const auto& v) {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, Bytes>)
          put_bytes_field(out, 16, v.data);
        else
          scalar(v);
      },
      m.value);
  return out;
}

}  // namespace

std::vector<std::uint8_t> encode_payload(const Payload& payload) {
  Buffer out;
  put_optional_varint(out, 1, payload.timestamp);
  for (const auto& m : payload.metrics) put_message_field(out, 2, metric(m));
  put_optional_varint(out, 3, payload.seq);
  if (payload.uuid) put_bytes_field(out, 4, *payload.uuid);
  if (payload.body) put_bytes_field(out, 5, payload.body->data);
  return out;
}

}  // namespace unima::sparkplug
