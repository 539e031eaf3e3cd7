#pragma once
// The bridge's register space as the request handler sees it.

#include "banks/register_space.hpp"
#include "modbus/register_model.hpp"

namespace unima::app {

class BankModel final : public modbus::RegisterModel {
 public:
  explicit BankModel(banks::RegisterSpace& space) : space_(space) {}
  bool read_registers(std::uint16_t first, std::span<std::uint16_t> out) override { return space_.read(first, out); }
  bool write_registers(std::uint16_t first, std::span<const std::uint16_t> values) override {
    return space_.write(first, values);
  }

 private:
  banks::RegisterSpace& space_;
};

}  // namespace unima::app
