#include "values/current_values.hpp"

#include "values/store_snapshot.hpp"

namespace unima::values {

CurrentValues::CurrentValues(const banks::RegisterStore& store, const ValueModel& model) : store_(store), model_(model) {}

std::uint64_t CurrentValues::store_changes() const {
  std::uint64_t sum = 0;
  for (const auto bank : banks::all_banks) sum += store_.changes(bank);
  return sum;
}

const Snapshot& CurrentValues::snapshot() {
  if (const auto now = store_changes(); now != snapshot_at_) {
    snapshot_ = snapshot_of(store_);
    snapshot_at_ = now;
  }
  return snapshot_;
}

const std::vector<Value>& CurrentValues::of(banks::BankId bank) {
  auto& evaluated = banks_[banks::index_of(bank)];
  if (const auto now = store_.changes(bank); now != evaluated.at) {
    evaluated.values = model_.evaluate(bank, snapshot());
    evaluated.at = now;
    ++evaluations_;
  }
  return evaluated.values;
}

}  // namespace unima::values
