#include "state/state_image.hpp"

namespace unima::state {

bool valid_index(PersistedValue::Kind kind, std::uint16_t index) {
  switch (kind) {
    case PersistedValue::Kind::w: return index < w_registers;
    case PersistedValue::Kind::x: return index < x_registers;
    case PersistedValue::Kind::output: return index >= 1 && index <= user_outputs;
  }
  return false;
}

void StateImage::apply(const PersistedValue& value) {
  switch (value.kind) {
    case PersistedValue::Kind::w: w_[value.index] = value.value; break;
    case PersistedValue::Kind::x: x_ = value.value; break;
    case PersistedValue::Kind::output: outputs_[value.index - 1] = value.value; break;
  }
}

std::vector<PersistedValue> StateImage::values() const {
  std::vector<PersistedValue> all;
  for (std::uint16_t i = 0; i < w_registers; ++i)
    if (w_[i]) all.push_back({PersistedValue::Kind::w, i, *w_[i]});
  if (x_) all.push_back({PersistedValue::Kind::x, 0, *x_});
  for (std::uint16_t n = 1; n <= user_outputs; ++n)
    if (outputs_[n - 1]) all.push_back({PersistedValue::Kind::output, n, *outputs_[n - 1]});
  return all;
}

}  // namespace unima::state
