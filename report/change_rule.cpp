#include "report/change_rule.hpp"

#include <cmath>

namespace unima::report {

bool counts_as_changed(const values::Value& published, const values::Value& now, double deadband) {
  const auto* before = std::get_if<double>(&published.reading);
  const auto* after = std::get_if<double>(&now.reading);
  if (before && after) return std::abs(*after - *before) > deadband;
  return !(published.reading == now.reading);  // null, booleans and text: any change
}

}  // namespace unima::report
