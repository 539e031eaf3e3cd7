#pragma once
// Plausible, changing register values for the `sim` transport (SPEC §6), deterministic
// for a given seed, so that the demo and tests see the same plant every run. Pure: the
// daemon's timer calls tick().

#include <cstdint>
#include <vector>

#include "banks/device_table.hpp"
#include "unimabus/telegram.hpp"

namespace unima::unimabus {

struct SimDevice {
  std::uint8_t address = 0;
  std::uint8_t slot = 0;
  std::uint16_t length = 0;
  const banks::DeviceTable* table = nullptr;  // shapes the values by register kind, if known
};

class SimGenerator {
 public:
  SimGenerator(std::uint32_t seed, std::vector<SimDevice> devices) : seed_(seed), devices_(std::move(devices)) {}

  /// One telegram per device carrying all its registers; every call advances time one step.
  std::vector<Telegram> tick();

 private:
  std::uint16_t value(const SimDevice& device, std::size_t device_index, std::uint16_t offset) const;

  std::uint32_t seed_;
  std::vector<SimDevice> devices_;
  std::uint64_t step_ = 0;
};

}  // namespace unima::unimabus
