#include "modbus/plc_numbers.hpp"

namespace unima::modbus {

namespace {

unsigned first_number(PlcTable table, PlcDigits digits) {
  if (digits == PlcDigits::five) return table == PlcTable::input ? 30001 : 40001;
  return table == PlcTable::input ? 300001 : 400001;
}

}  // namespace

unsigned plc_number(PlcTable table, std::uint16_t address, PlcDigits digits) {
  return first_number(table, digits) + address;
}

PlcDigits plc_digits_for(std::uint16_t highest) {
  return highest <= highest_five_digit_address ? PlcDigits::five : PlcDigits::six;
}

std::optional<PlcRegister> read_plc_number(unsigned long number) {
  for (const auto digits : {PlcDigits::five, PlcDigits::six}) {
    for (const auto table : {PlcTable::input, PlcTable::holding}) {
      const unsigned long first = first_number(table, digits);
      const unsigned long last = digits == PlcDigits::five ? first + highest_five_digit_address : first + 0xFFFF;
      if (number >= first && number <= last) return PlcRegister{table, static_cast<std::uint16_t>(number - first), digits};
    }
  }
  return std::nullopt;
}

}  // namespace unima::modbus
