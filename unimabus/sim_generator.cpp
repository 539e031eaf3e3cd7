#include "unimabus/sim_generator.hpp"

#include <cmath>
#include <numbers>
#include <string_view>

namespace unima::unimabus {

namespace {

// splitmix64: a fixed, portable hash, so values depend on the seed and nothing else.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

constexpr std::string_view display_text = "UNIMA BRIDGE    SIMULATED PLANT ";

}  // namespace

std::vector<Telegram> SimGenerator::tick() {
  std::vector<Telegram> telegrams;
  telegrams.reserve(devices_.size());
  for (std::size_t d = 0; d < devices_.size(); ++d) {
    const auto& device = devices_[d];
    Telegram t;
    t.address = device.address;
    t.slot = device.slot;
    t.offset = 0;
    if (device.slot == 0) t.device = device.table;  // a unit's components share its address
    t.values.reserve(device.length);
    for (std::uint16_t offset = 0; offset < device.length; ++offset) t.values.push_back(value(device, d, offset));
    telegrams.push_back(std::move(t));
  }
  ++step_;
  return telegrams;
}

std::uint16_t SimGenerator::value(const SimDevice& device, std::size_t device_index, std::uint16_t offset) const {
  const std::uint64_t identity = mix(seed_ ^ mix(device_index * 131 + offset));
  const auto kind = device.table && offset < device.table->length() ? device.table->registers[offset].kind
                                                                     : banks::RegisterKind::analog;
  switch (kind) {
    case banks::RegisterKind::reserve: return 0;
    case banks::RegisterKind::bits: {
      // Most bits hold still; one flips every few steps, as a status word does.
      const auto stable = static_cast<std::uint16_t>(identity & 0x0F0F);
      const unsigned flipping = identity % 16;
      const bool on = ((step_ + identity) / (3 + identity % 5)) % 2 != 0;
      return static_cast<std::uint16_t>(on ? stable | (1u << flipping) : stable & ~(1u << flipping));
    }
    case banks::RegisterKind::u32_low:
    case banks::RegisterKind::u32_high: {
      // A 32-bit counter (operating hours, energy) that only goes up; both halves come
      // from the pair's low-word offset so they stay consistent.
      const std::uint16_t low_offset = kind == banks::RegisterKind::u32_low ? offset : offset - 1;
      const std::uint64_t counter = mix(seed_ ^ mix(device_index * 131 + low_offset)) % 5'000'000 + step_;
      return static_cast<std::uint16_t>(kind == banks::RegisterKind::u32_low ? counter & 0xFFFF : counter >> 16);
    }
    case banks::RegisterKind::byte_pair:
      return static_cast<std::uint16_t>(((identity >> 8) % 128) << 8 | ((identity + step_) % 128));
    case banks::RegisterKind::ascii_pair: {
      const std::size_t at = (2 * offset) % display_text.size();
      return static_cast<std::uint16_t>(display_text[at] << 8 | display_text[(at + 1) % display_text.size()]);
    }
    default: break;
  }
  // Analog: a level of its own with a slow swing of a few percent and a little noise.
  const double level = 100.0 + static_cast<double>(identity % 900);
  const double period = 20.0 + static_cast<double>(identity % 40);
  const double swing = 0.05 * level * std::sin(2.0 * std::numbers::pi * static_cast<double>(step_) / period);
  const double noise = static_cast<double>(mix(identity ^ step_) % 5) - 2.0;
  return static_cast<std::uint16_t>(std::lround(level + swing + noise));
}

}  // namespace unima::unimabus
