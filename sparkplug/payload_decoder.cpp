// decode_payload: protobuf's wire format read back into sparkplug/payload.hpp, strictly
// and totally (sparkplug/payload_codec.hpp lists the rules). One cursor over the whole
// input with the end of the message being read, as protobuf's own parsers do ("push a
// limit"), so no read can pass the message it belongs to.

#include <bit>

#include <fmt/format.h>

#include "sparkplug/payload_codec.hpp"
#include "sparkplug/wire_type.hpp"

namespace unima::sparkplug {

namespace {

using enum WireType;

struct Field {
  std::uint32_t number = 0;
  WireType type = varint;
  std::size_t at = 0;  // its tag's first byte
};

class Decoder {
 public:
  explicit Decoder(std::span<const std::uint8_t> bytes) : bytes_(bytes), end_(bytes.size()) {}

  std::optional<DecodeError> error;

  bool payload(Payload& out) {
    message_ = "Payload";
    return fields([&](const Field& f) { return payload_field(f, out); });
  }

 private:
  bool fail(DecodeProblem problem, std::size_t at) {
    error = DecodeError{problem, at, message_, field_};
    return false;
  }

  // --- the wire ----------------------------------------------------------------------

  bool read_varint(std::uint64_t& value) {
    const auto start = pos_;
    value = 0;
    for (unsigned i = 0; i < 10; ++i) {
      if (pos_ >= end_) return fail(DecodeProblem::truncated, start);
      const std::uint8_t byte = bytes_[pos_++];
      // The tenth byte holds bit 63 alone: anything more is past 64 bits.
      if (i == 9 && byte > 1) return fail(DecodeProblem::overlong_varint, start);
      value |= std::uint64_t{byte & 0x7Fu} << (7 * i);
      if ((byte & 0x80) == 0) return true;
    }
    return fail(DecodeProblem::overlong_varint, start);  // unreachable: the tenth byte ends it
  }

  bool read_fixed(std::uint64_t& bits, unsigned size) {
    if (end_ - pos_ < size) return fail(DecodeProblem::truncated, pos_);
    bits = 0;
    for (unsigned i = 0; i < size; ++i) bits |= std::uint64_t{bytes_[pos_ + i]} << (8 * i);  // little-endian
    pos_ += size;
    return true;
  }

  bool read_length(std::size_t& length) {
    const auto start = pos_;
    std::uint64_t value = 0;
    if (!read_varint(value)) return false;
    if (value > end_ - pos_) return fail(DecodeProblem::length_past_end, start);
    length = static_cast<std::size_t>(value);
    return true;
  }

  bool read_tag(Field& field) {
    field_ = 0;
    field.at = pos_;
    std::uint64_t tag = 0;
    if (!read_varint(tag)) return false;
    // A tag is a uint32: field numbers go to 2^29 - 1 (the "Language Guide", field numbers).
    if (tag > 0xFFFFFFFFu || (tag >> 3) == 0) return fail(DecodeProblem::bad_tag, field.at);
    const auto type = static_cast<std::uint8_t>(tag & 7);
    if (type > static_cast<std::uint8_t>(fixed32)) return fail(DecodeProblem::bad_wire_type, field.at);
    field.number = static_cast<std::uint32_t>(tag >> 3);
    field.type = static_cast<WireType>(type);
    field_ = field.number;
    return true;
  }

  bool expect(const Field& field, WireType type) {
    return field.type == type || fail(DecodeProblem::wrong_wire_type, field.at);
  }

  // Every field of the message that ends at end_, each handed to `on_field`.
  template <typename OnField>
  bool fields(OnField&& on_field) {
    Field field;
    while (pos_ < end_)
      if (!read_tag(field) || !on_field(field)) return false;
    return true;
  }

  // A length-delimited field read as the message `name`, its fields handed to `on_field`.
  template <typename OnField>
  bool nested(const Field& field, std::string_view name, OnField&& on_field) {
    std::size_t length = 0;
    if (!expect(field, length_delimited) || !read_length(length)) return false;
    if (depth_ + 1 >= max_nesting) return fail(DecodeProblem::too_deep, field.at);
    const auto outer_end = end_;
    const auto outer_message = message_;
    end_ = pos_ + length;
    ++depth_;
    message_ = name;
    if (!fields(on_field)) return false;
    end_ = outer_end;
    --depth_;
    message_ = outer_message;
    field_ = field.number;
    return true;
  }

  bool skip(const Field& field) {
    std::uint64_t ignored = 0;
    std::size_t length = 0;
    switch (field.type) {
      case varint: return read_varint(ignored);
      case fixed64: return read_fixed(ignored, 8);
      case fixed32: return read_fixed(ignored, 4);
      case length_delimited:
        if (!read_length(length)) return false;
        pos_ += length;
        return true;
      case start_group: return skip_group(field);
      case end_group: break;
    }
    return fail(DecodeProblem::unmatched_group, field.at);
  }

  // An unknown group: its fields up to the end-group of the same number (proto2 "groups").
  bool skip_group(const Field& group) {
    if (depth_ + 1 >= max_nesting) return fail(DecodeProblem::too_deep, group.at);
    ++depth_;
    Field field;
    while (pos_ < end_) {
      if (!read_tag(field)) return false;
      if (field.type == end_group) {
        if (field.number != group.number) return fail(DecodeProblem::unmatched_group, field.at);
        --depth_;
        return true;
      }
      if (!skip(field)) return false;
    }
    return fail(DecodeProblem::unmatched_group, group.at);
  }

  // --- typed fields ------------------------------------------------------------------

  bool uint64_field(const Field& field, std::uint64_t& value) { return expect(field, varint) && read_varint(value); }

  template <typename T>
  bool optional_uint64(const Field& field, std::optional<T>& value) {
    std::uint64_t raw = 0;
    if (!uint64_field(field, raw)) return false;
    value = static_cast<T>(raw);
    return true;
  }

  // A uint32 field keeps the varint's low 32 bits, as protobuf's parsers do.
  template <typename T>
  bool optional_uint32(const Field& field, std::optional<T>& value) {
    std::uint64_t raw = 0;
    if (!uint64_field(field, raw)) return false;
    value = static_cast<T>(static_cast<std::uint32_t>(raw));
    return true;
  }

  bool optional_bool(const Field& field, std::optional<bool>& value) {
    std::uint64_t raw = 0;
    if (!uint64_field(field, raw)) return false;
    value = raw != 0;
    return true;
  }

  bool bytes_field(const Field& field, std::string& value) {
    std::size_t length = 0;
    if (!expect(field, length_delimited) || !read_length(length)) return false;
    value.assign(reinterpret_cast<const char*>(bytes_.data() + pos_), length);
    pos_ += length;
    return true;
  }

  // A message we keep encoded: a second occurrence is merged, which for protobuf's wire
  // format is the two encodings one after the other.
  bool append_encoded(const Field& field, std::string& encoded) {
    std::string more;
    if (!bytes_field(field, more)) return false;
    encoded += more;
    return true;
  }

  template <typename Value>
  bool encoded_value(const Field& field, Value& value) {
    auto* held = std::get_if<EncodedMessage>(&value);
    if (!held || held->field != field.number) held = &value.template emplace<EncodedMessage>(EncodedMessage{field.number, {}});
    return append_encoded(field, held->bytes);
  }

  // The `oneof value` alternatives Metric (from field 10) and PropertyValue (from field 3)
  // share: int_value, long_value, float_value, double_value, boolean_value, string_value.
  // `handled` is false for any other field.
  template <typename Value>
  bool scalar_value(const Field& field, std::uint32_t int_field, Value& value, bool& handled) {
    handled = true;
    std::uint64_t raw = 0;
    switch (field.number - int_field) {
      case 0:
        if (!uint64_field(field, raw)) return false;
        value = static_cast<std::uint32_t>(raw);
        return true;
      case 1:
        if (!uint64_field(field, raw)) return false;
        value = raw;
        return true;
      case 2:
        if (!expect(field, fixed32) || !read_fixed(raw, 4)) return false;
        value = std::bit_cast<float>(static_cast<std::uint32_t>(raw));
        return true;
      case 3:
        if (!expect(field, fixed64) || !read_fixed(raw, 8)) return false;
        value = std::bit_cast<double>(raw);
        return true;
      case 4:
        if (!uint64_field(field, raw)) return false;
        value = raw != 0;
        return true;
      case 5: return bytes_field(field, value.template emplace<std::string>());
      default: handled = false; return true;
    }
  }

  // --- the messages (§6.4.2–§6.4.8) --------------------------------------------------

  bool payload_field(const Field& f, Payload& out) {
    switch (f.number) {
      case 1: return optional_uint64(f, out.timestamp);
      case 2: {
        auto& metric = out.metrics.emplace_back();
        return nested(f, "Metric", [&](const Field& mf) { return metric_field(mf, metric); });
      }
      case 3: return optional_uint64(f, out.seq);
      case 4: return bytes_field(f, out.uuid.emplace());
      case 5: return bytes_field(f, out.body.emplace().data);
      default: return skip(f);
    }
  }

  bool metric_field(const Field& f, Metric& m) {
    switch (f.number) {
      case 1: return bytes_field(f, m.name.emplace());
      case 2: return optional_uint64(f, m.alias);
      case 3: return optional_uint64(f, m.timestamp);
      case 4: return optional_uint32(f, m.datatype);
      case 5: return optional_bool(f, m.is_historical);
      case 6: return optional_bool(f, m.is_transient);
      case 7: return optional_bool(f, m.is_null);
      case 8: return append_encoded(f, (m.metadata ? *m.metadata : m.metadata.emplace()).data);
      case 9: {
        auto& set = m.properties ? *m.properties : m.properties.emplace();
        return nested(f, "PropertySet", [&](const Field& sf) { return property_set_field(sf, set); });
      }
      case 16: return bytes_field(f, m.value.emplace<Bytes>().data);
      case 17:
      case 18:
      case 19: return encoded_value(f, m.value);
      default: {
        bool handled = false;
        if (!scalar_value(f, 10, m.value, handled)) return false;
        return handled || skip(f);
      }
    }
  }

  bool property_set_field(const Field& f, PropertySet& set) {
    switch (f.number) {
      case 1: return bytes_field(f, set.keys.emplace_back());
      case 2: {
        auto& value = set.values.emplace_back();
        return nested(f, "PropertyValue", [&](const Field& vf) { return property_value_field(vf, value); });
      }
      default: return skip(f);
    }
  }

  bool property_set_list_field(const Field& f, PropertySetList& list) {
    if (f.number != 1) return skip(f);
    auto& set = list.propertysets.emplace_back();
    return nested(f, "PropertySet", [&](const Field& sf) { return property_set_field(sf, set); });
  }

  bool property_value_field(const Field& f, PropertyValue& v) {
    switch (f.number) {
      case 1: return optional_uint32(f, v.type);
      case 2: return optional_bool(f, v.is_null);
      case 9: {
        auto* set = std::get_if<PropertySet>(&v.value);
        if (!set) set = &v.value.emplace<PropertySet>();
        return nested(f, "PropertySet", [&](const Field& sf) { return property_set_field(sf, *set); });
      }
      case 10: {
        auto* list = std::get_if<PropertySetList>(&v.value);
        if (!list) list = &v.value.emplace<PropertySetList>();
        return nested(f, "PropertySetList", [&](const Field& lf) { return property_set_list_field(lf, *list); });
      }
      case 11: return encoded_value(f, v.value);
      default: {
        bool handled = false;
        if (!scalar_value(f, 3, v.value, handled)) return false;
        return handled || skip(f);
      }
    }
  }

  std::span<const std::uint8_t> bytes_;
  std::size_t pos_ = 0;
  std::size_t end_;
  unsigned depth_ = 0;  // the messages and groups entered below the payload
  std::string_view message_;
  std::uint32_t field_ = 0;
};

std::string_view problem_text(DecodeProblem problem) {
  switch (problem) {
    case DecodeProblem::truncated: return "the input ends inside a field";
    case DecodeProblem::overlong_varint: return "a varint longer than 64 bits";
    case DecodeProblem::bad_tag: return "a tag with field number 0 or past 2^29 - 1";
    case DecodeProblem::bad_wire_type: return "wire type 6 or 7, which protobuf does not define";
    case DecodeProblem::wrong_wire_type: return "a wire type the schema does not give this field";
    case DecodeProblem::length_past_end: return "a length past the end of its message";
    case DecodeProblem::too_deep: return "messages or groups nested too deep";
    case DecodeProblem::unmatched_group: return "a group that does not end where it should";
  }
  return "?";
}

}  // namespace

std::string describe(const DecodeError& error) {
  if (error.field == 0) return fmt::format("byte {}, {}: {}", error.offset, error.message, problem_text(error.problem));
  return fmt::format("byte {}, {} field {}: {}", error.offset, error.message, error.field, problem_text(error.problem));
}

DecodeResult decode_payload(std::span<const std::uint8_t> bytes) {
  Decoder decoder(bytes);
  Payload payload;
  if (!decoder.payload(payload)) return {std::nullopt, decoder.error};
  return {std::move(payload), std::nullopt};
}

}  // namespace unima::sparkplug
