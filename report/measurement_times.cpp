#include "report/measurement_times.hpp"

namespace unima::report {

void MeasurementTimes::note(std::span<const std::uint64_t> changes, Time changed_at) {
  if (banks_.size() != changes.size()) {
    banks_.assign(changes.size(), Bank{});
    for (std::size_t i = 0; i < changes.size(); ++i) banks_[i] = {changes[i], changed_at};
    return;
  }
  for (std::size_t i = 0; i < changes.size(); ++i)
    if (banks_[i].changes != changes[i]) banks_[i] = {changes[i], changed_at};
}

}  // namespace unima::report
