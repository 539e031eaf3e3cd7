// Fuzz target: an NCMD or DCMD as a Sparkplug host — or anything else that may publish on
// the broker — sends it (SPEC §16): sparkplug::decode_payload, then what the session does
// with a command's metrics (its name or alias, its datatype, the value read as that type
// by sparkplug::number_of / boolean_of), and the payload encoded again.
//
// Input: the MQTT message's payload, all of it.

#include <cstddef>
#include <cstdint>
#include <span>

#include "fuzz/fuzz_check.hpp"
#include "sparkplug/metric_value.hpp"
#include "sparkplug/payload_codec.hpp"

namespace {

using namespace unima::sparkplug;

void read_like_a_command(const Metric& metric) {
  const auto type = metric.datatype.value_or(DataType::Unknown);
  FUZZ_CHECK(!data_type_name(type).empty());
  const auto number = number_of(metric.value, type);
  if (number) FUZZ_CHECK(is_number(type));
  if (number && is_integer(type)) FUZZ_CHECK(*number == *number);  // an integer is never NaN
  if (boolean_of(metric.value, type)) FUZZ_CHECK(type == DataType::Boolean && !number);
  if (metric.properties) {
    const auto* unit = metric.properties->find("engUnit");
    if (unit) FUZZ_CHECK(!metric.properties->keys.empty() && !metric.properties->values.empty());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto result = decode_payload(std::span(data, size));
  FUZZ_CHECK(result.payload.has_value() != result.error.has_value());
  if (result.error) {
    FUZZ_CHECK(result.error->offset <= size);
    FUZZ_CHECK(!result.error->message.empty());
    FUZZ_CHECK(!describe(*result.error).empty());
    return 0;
  }
  for (const auto& metric : result.payload->metrics) read_like_a_command(metric);

  // Decoded, encoded, decoded again: the same payload. Compared as bytes, which hold a
  // float's bits exactly (a NaN is not equal to itself). The encoder only ever drops what
  // protobuf lets a reader drop (unknown fields, the earlier of two occurrences, longer
  // forms of a varint), so it never writes more than it was given.
  const auto encoded = encode_payload(*result.payload);
  FUZZ_CHECK(encoded.size() <= size);
  const auto again = decode_payload(encoded);
  FUZZ_CHECK(again.payload.has_value());
  FUZZ_CHECK(encode_payload(*again.payload) == encoded);
  FUZZ_CHECK(again.payload->metrics.size() == result.payload->metrics.size());
  return 0;
}
