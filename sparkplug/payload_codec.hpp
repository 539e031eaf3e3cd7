#pragma once
// Sparkplug B payloads to bytes and back (SPEC §16): protobuf's wire format (the
// "Encoding" guide of Protocol Buffers: base-128 varints, tags of field number and wire
// type, length-delimited messages, little-endian fixed32/fixed64) for the messages of
// sparkplug/payload.hpp, written here from the field numbers of the Sparkplug 3.0
// specification.
//
// Why our own and not libprotobuf-c (Debian has it): the bridge needs four small messages,
// and protobuf-c would need a schema file and generated code — the only published schema
// is Eclipse Tahu's sparkplug_b.proto, under the EPL-2.0, which we do not ship — while
// NCMD and DCMD come from outside and their decoder is best one we own and fuzz
// (fuzz/sparkplug_payload_fuzzer.cpp): about 400 lines with no code generator.
//
// The encoder writes proto2's form: fields in number order, every present optional field,
// repeated fields unpacked (proto2's default; none of ours is a packable scalar anyway).
// Signed values are not zig-zag encoded: Sparkplug has no sint fields; an Int8..Int32 is
// the two's complement in uint32 int_value, an Int64 in uint64 long_value
// (sparkplug/metric_value.hpp).
//
// The decoder is strict and total: whatever the bytes, it returns a Payload or a
// DecodeError and never throws, reads past its input or recurses without bound. Beyond
// protobuf's own rules it refuses a known field of the wrong wire type. As protobuf does,
// it skips unknown fields (groups included), keeps the last of a repeated scalar, merges a
// repeated message field, keeps the low 32 bits of a varint in a uint32 field, and takes
// any non-zero varint as true. Strings are not checked for UTF-8 (proto2 does not): a name
// that goes into a log line goes through platform::log_safe.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sparkplug/payload.hpp"

namespace unima::sparkplug {

/// The bytes of `payload`, as an MQTT message's payload.
std::vector<std::uint8_t> encode_payload(const Payload& payload);

enum class DecodeProblem : std::uint8_t {
  truncated,          // the input ends inside a tag, varint or fixed-size value
  overlong_varint,    // more than 10 bytes, or a value past 64 bits
  bad_tag,            // field number 0 or past 2^29 - 1, or a tag past 32 bits
  bad_wire_type,      // wire type 6 or 7, which protobuf does not define
  wrong_wire_type,    // a field of the schema with another wire type than the schema's
  length_past_end,    // a length-delimited field longer than what is left of its message
  too_deep,           // messages or groups nested deeper than max_nesting
  unmatched_group,    // an end-group without its start-group, or a group never closed
};

/// Where decoding stopped and why.
struct DecodeError {
  DecodeProblem problem = DecodeProblem::truncated;
  std::size_t offset = 0;      // the input's byte at which the problem was found
  std::string_view message;    // "Payload", "Metric", "PropertySet", "PropertyValue", "PropertySetList"
  std::uint32_t field = 0;     // the field being read, 0 before its tag
  bool operator==(const DecodeError&) const = default;
};

/// "byte 17, Metric field 4: a wire type the schema does not give this field": for a counter's
/// log line.
std::string describe(const DecodeError& error);

/// Payload ⊃ Metric ⊃ PropertySet ⊃ PropertyValue ⊃ PropertySet ...: how deep messages (and
/// unknown groups) may nest. The bridge's own payloads go four deep; protobuf's default
/// limit is 100.
inline constexpr unsigned max_nesting = 32;

struct DecodeResult {
  std::optional<Payload> payload;    // when the bytes were a payload
  std::optional<DecodeError> error;  // else why not; exactly one of the two is set
};

DecodeResult decode_payload(std::span<const std::uint8_t> bytes);
inline DecodeResult decode_payload(std::string_view bytes) {
  return decode_payload(std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
}

}  // namespace unima::sparkplug
