// The PLC-style register numbers (modbus/plc_numbers): what `map` prints and what a config
// key holding one is warned about.

#include <gtest/gtest.h>

#include "modbus/plc_numbers.hpp"

namespace unima::modbus {
namespace {

TEST(PlcNumbers, CountFromOneInTheirTableInFiveOrSixDigits) {
  EXPECT_EQ(plc_number(PlcTable::input, 0x0000, PlcDigits::five), 30001u);
  EXPECT_EQ(plc_number(PlcTable::holding, 0x0000, PlcDigits::five), 40001u);
  EXPECT_EQ(plc_number(PlcTable::holding, 9998, PlcDigits::five), 49999u);
  EXPECT_EQ(plc_number(PlcTable::input, 0x1000, PlcDigits::six), 304097u);
  EXPECT_EQ(plc_number(PlcTable::holding, 0xFFFF, PlcDigits::six), 465536u);
  EXPECT_EQ(plc_digits_for(9998), PlcDigits::five);
  EXPECT_EQ(plc_digits_for(9999), PlcDigits::six);
}

TEST(PlcNumbers, ReadBackToTheAddressTheyMean) {
  const auto holding = read_plc_number(40001);
  ASSERT_TRUE(holding);
  EXPECT_EQ(holding->table, PlcTable::holding);
  EXPECT_EQ(holding->address, 0x0000);
  EXPECT_EQ(read_plc_number(30010)->address, 9);
  EXPECT_EQ(read_plc_number(30010)->table, PlcTable::input);
  EXPECT_EQ(read_plc_number(400001)->digits, PlcDigits::six);
  EXPECT_EQ(read_plc_number(465536)->address, 0xFFFF);
  for (unsigned long other : {0ul, 30000ul, 40000ul, 50000ul, 300000ul, 365537ul, 400000ul, 465537ul})
    EXPECT_FALSE(read_plc_number(other)) << other;
}

}  // namespace
}  // namespace unima::modbus
