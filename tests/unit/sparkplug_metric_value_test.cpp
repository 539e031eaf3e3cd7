// sparkplug/metric_value (Sparkplug 3.0 §6.4.17): which field holds a value of each data
// type, signed integers as two's complement, and what a host's command may send.

#include <gtest/gtest.h>

#include "sparkplug/metric_value.hpp"

namespace unima::sparkplug {
namespace {

TEST(SparkplugMetricValue, IntegersGoInTheFieldTheirTypeNames) {
  EXPECT_EQ(integer_value(DataType::Int8, -1), MetricValue(std::uint32_t{0xFFFFFFFF}));
  EXPECT_EQ(integer_value(DataType::Int16, -87), MetricValue(std::uint32_t{0xFFFFFFA9}));
  EXPECT_EQ(integer_value(DataType::Int32, -2), MetricValue(std::uint32_t{0xFFFFFFFE}));
  EXPECT_EQ(integer_value(DataType::UInt16, 65535), MetricValue(std::uint32_t{65535}));
  EXPECT_EQ(integer_value(DataType::UInt32, 4294967295), MetricValue(std::uint32_t{4294967295}));
  EXPECT_EQ(integer_value(DataType::Int64, -1), MetricValue(~std::uint64_t{0}));
  EXPECT_EQ(integer_value(DataType::UInt64, 7), MetricValue(std::uint64_t{7}));
  EXPECT_EQ(integer_value(DataType::DateTime, 1700000000000), MetricValue(std::uint64_t{1700000000000}));
}

TEST(SparkplugMetricValue, ASignedValueIsReadSignExtendedOrInItsOwnWidth) {
  EXPECT_EQ(number_of(std::uint32_t{0xFFFFFFA9}, DataType::Int16), -87.0) << "as Tahu's Java encoder sends it";
  EXPECT_EQ(number_of(std::uint32_t{0xFFA9}, DataType::Int16), -87.0) << "the type's own 16 bits";
  EXPECT_EQ(number_of(std::uint32_t{0x7FFF}, DataType::Int16), 32767.0);
  EXPECT_EQ(number_of(std::uint32_t{0xFFFF0001}, DataType::Int16), std::nullopt) << "no Int16";
  EXPECT_EQ(number_of(std::uint32_t{0x100}, DataType::Int8), std::nullopt);
  EXPECT_EQ(number_of(std::uint32_t{0x80}, DataType::Int8), -128.0);
  EXPECT_EQ(number_of(~std::uint64_t{0x7F}, DataType::Int8), -128.0) << "sign-extended to 64 bits in long_value";
  EXPECT_EQ(number_of(std::uint32_t{0x80000000}, DataType::Int32), -2147483648.0);
  EXPECT_EQ(number_of(~std::uint64_t{0}, DataType::Int64), -1.0);
}

TEST(SparkplugMetricValue, AnUnsignedValueMustFitItsType) {
  EXPECT_EQ(number_of(std::uint32_t{65535}, DataType::UInt16), 65535.0);
  EXPECT_EQ(number_of(std::uint32_t{65536}, DataType::UInt16), std::nullopt);
  EXPECT_EQ(number_of(std::uint32_t{256}, DataType::UInt8), std::nullopt);
  EXPECT_EQ(number_of(std::uint64_t{4294967295}, DataType::UInt32), 4294967295.0)
      << "a UInt32 in long_value, as Ignition sent it before the specification's issue 102";
  EXPECT_EQ(number_of(std::uint64_t{4294967296}, DataType::UInt32), std::nullopt);
}

TEST(SparkplugMetricValue, FloatsBooleansAndMismatches) {
  EXPECT_EQ(number_of(1.5f, DataType::Float), 1.5);
  EXPECT_EQ(number_of(12.3f, DataType::Float), 12.3) << "the decimal written, not 12.300000190734863";
  EXPECT_EQ(number_of(3276.6f, DataType::Float), 3276.6);
  EXPECT_EQ(number_of(2.25, DataType::Double), 2.25);
  EXPECT_EQ(number_of(2.25, DataType::Float), 2.25) << "a host's double for a Float metric";
  EXPECT_EQ(number_of(std::uint32_t{1}, DataType::Float), std::nullopt) << "an integer field for a Float";
  EXPECT_EQ(number_of(1.5f, DataType::Int16), std::nullopt) << "a float field for an Int16";
  EXPECT_EQ(number_of(MetricValue{}, DataType::UInt16), std::nullopt) << "null";
  EXPECT_EQ(number_of(std::string("1"), DataType::String), std::nullopt);
  EXPECT_EQ(number_of(true, DataType::Boolean), std::nullopt) << "a Boolean is no number";
  EXPECT_EQ(boolean_of(true, DataType::Boolean), true);
  EXPECT_EQ(boolean_of(std::uint32_t{1}, DataType::Boolean), std::nullopt);
  EXPECT_EQ(boolean_of(true, DataType::UInt16), std::nullopt);
  EXPECT_TRUE(is_integer(DataType::DateTime));
  EXPECT_FALSE(is_integer(DataType::Float));
  EXPECT_TRUE(is_number(DataType::Double));
  EXPECT_FALSE(is_number(DataType::String));
}

}  // namespace
}  // namespace unima::sparkplug
