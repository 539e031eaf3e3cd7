#pragma once
// The four capture indicators of the seed's monitor (seed 004 §8, SPEC §5): each watches
// one address + register and keeps the last value seen on the bus, whether it was read or
// written, and when. Pure: the time comes from the transaction.

#include <chrono>
#include <cstdint>
#include <optional>
#include <vector>

#include "modbus/register_capture.hpp"

namespace unima::monitor {

struct IndicatorSpec {
  std::uint8_t address = 0;
  std::uint16_t reg = 0;
  bool operator==(const IndicatorSpec&) const = default;
};

struct IndicatorReading {
  std::uint16_t value = 0;
  modbus::CaptureAccess access = modbus::CaptureAccess::read;
  std::chrono::system_clock::time_point time;
};

class CaptureIndicators {
 public:
  static constexpr std::size_t max_indicators = 4;

  /// At most max_indicators (the config checks it).
  explicit CaptureIndicators(std::vector<IndicatorSpec> specs = {});

  bool empty() const { return specs_.empty(); }
  std::size_t size() const { return specs_.size(); }
  const IndicatorSpec& spec(std::size_t i) const { return specs_[i]; }
  const std::optional<IndicatorReading>& reading(std::size_t i) const { return readings_[i]; }

  void observe(const modbus::CapturedRegisters& captured, std::chrono::system_clock::time_point time);
  /// For a reload: an indicator watching the same address + register keeps its reading.
  void take_readings_from(const CaptureIndicators& old);

 private:
  std::vector<IndicatorSpec> specs_;
  std::vector<std::optional<IndicatorReading>> readings_;
};

}  // namespace unima::monitor
