#include "monitor/capture_indicators.hpp"

namespace unima::monitor {

CaptureIndicators::CaptureIndicators(std::vector<IndicatorSpec> specs)
    : specs_(std::move(specs)), readings_(specs_.size()) {}

void CaptureIndicators::observe(const modbus::CapturedRegisters& captured, std::chrono::system_clock::time_point time) {
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    if (specs_[i].address != captured.address) continue;
    if (const auto value = captured.value_of(specs_[i].reg)) readings_[i] = IndicatorReading{*value, captured.access, time};
  }
}

void CaptureIndicators::take_readings_from(const CaptureIndicators& old) {
  for (std::size_t i = 0; i < specs_.size(); ++i)
    for (std::size_t j = 0; j < old.specs_.size(); ++j)
      if (specs_[i] == old.specs_[j] && old.readings_[j]) readings_[i] = old.readings_[j];
}

}  // namespace unima::monitor
