#include "sparkplug/metric_value.hpp"

#include <array>
#include <charconv>

namespace unima::sparkplug {

namespace {

// How many bits an integer type has, and whether it is signed.
struct IntegerShape {
  unsigned bits;
  bool is_signed;
};

std::optional<IntegerShape> shape_of(DataType type) {
  switch (type) {
    case DataType::Int8: return IntegerShape{8, true};
    case DataType::Int16: return IntegerShape{16, true};
    case DataType::Int32: return IntegerShape{32, true};
    case DataType::Int64: return IntegerShape{64, true};
    case DataType::UInt8: return IntegerShape{8, false};
    case DataType::UInt16: return IntegerShape{16, false};
    case DataType::UInt32: return IntegerShape{32, false};
    case DataType::UInt64:
    case DataType::DateTime: return IntegerShape{64, false};
    default: return std::nullopt;
  }
}

// The raw field of width `field_bits` read as an integer of `shape`: the type's own bits,
// when everything above them is zero or (signed) the sign extended.
std::optional<double> integer_of(std::uint64_t raw, unsigned field_bits, IntegerShape shape) {
  if (shape.bits >= field_bits) {
    if (shape.is_signed && shape.bits == field_bits)
      return field_bits == 64 ? static_cast<double>(static_cast<std::int64_t>(raw))
                              : static_cast<double>(static_cast<std::int32_t>(static_cast<std::uint32_t>(raw)));
    return static_cast<double>(raw);
  }
  const std::uint64_t type_mask = (std::uint64_t{1} << shape.bits) - 1;
  const std::uint64_t field_mask = field_bits == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << field_bits) - 1;
  const std::uint64_t low = raw & type_mask, high = raw & field_mask & ~type_mask;
  if (!shape.is_signed) return high == 0 ? std::optional<double>(static_cast<double>(low)) : std::nullopt;
  const bool negative = (low >> (shape.bits - 1)) & 1;
  const bool sign_extended = high == (field_mask & ~type_mask) && negative;
  if (high != 0 && !sign_extended) return std::nullopt;
  return negative ? static_cast<double>(static_cast<std::int64_t>(low) - static_cast<std::int64_t>(type_mask) - 1)
                  : static_cast<double>(low);
}

// The decimal a Float stands for: the shortest text that reads back as the same float. A
// host that writes 12.3 into a Float sends 12.30000019…, which widened as it is would be
// no value a register's tenths hold.
double decimal_of(float number) {
  std::array<char, 32> text{};
  const auto written = std::to_chars(text.data(), text.data() + text.size(), number);
  double decimal = number;
  std::from_chars(text.data(), written.ptr, decimal);
  return decimal;
}

}  // namespace

bool is_integer(DataType type) { return shape_of(type).has_value(); }

bool is_number(DataType type) { return is_integer(type) || type == DataType::Float || type == DataType::Double; }

MetricValue integer_value(DataType type, std::int64_t value) {
  const auto shape = shape_of(type);
  if (shape && shape->bits == 64) return static_cast<std::uint64_t>(value);
  // Two's complement sign-extended to 32 bits, as Tahu's Java encoder writes an Int8..Int32.
  return static_cast<std::uint32_t>(static_cast<std::int32_t>(value));
}

std::optional<double> number_of(const MetricValue& value, DataType type) {
  if (const auto shape = shape_of(type)) {
    if (const auto* raw = std::get_if<std::uint32_t>(&value)) return integer_of(*raw, 32, *shape);
    if (const auto* raw = std::get_if<std::uint64_t>(&value)) return integer_of(*raw, 64, *shape);
    return std::nullopt;
  }
  if (type != DataType::Float && type != DataType::Double) return std::nullopt;
  if (const auto* number = std::get_if<float>(&value)) return decimal_of(*number);
  if (const auto* number = std::get_if<double>(&value)) return *number;
  return std::nullopt;
}

std::optional<bool> boolean_of(const MetricValue& value, DataType type) {
  const auto* flag = std::get_if<bool>(&value);
  if (type != DataType::Boolean || !flag) return std::nullopt;
  return *flag;
}

}  // namespace unima::sparkplug
