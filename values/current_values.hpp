#pragma once
// The values of a running store now, evaluated at most once per change of the store: MQTT,
// Sparkplug and the page each ask for them after the same wake-up (io/store_changes), and
// the second and third asker get what the first made. A bank's values are evaluated when
// first asked for after a change of that bank (banks::RegisterStore::changes, which counts
// a mapped source's change for A, B and C too); the registers are read once per change of
// any bank. Pure: the store and the model are given.

#include <cstdint>
#include <vector>

#include "banks/register_store.hpp"
#include "values/value_model.hpp"

namespace unima::values {

class CurrentValues {
 public:
  /// Both must outlive this (io::Banks holds all three).
  CurrentValues(const banks::RegisterStore& store, const ValueModel& model);

  /// The store's registers as of its latest change (values/store_snapshot).
  const Snapshot& snapshot();
  /// `bank`'s values as of its latest change. Precondition: the bank has values.
  const std::vector<Value>& of(banks::BankId bank);
  /// How many times a bank's values were evaluated (what the sharing saves, for tests).
  std::uint64_t evaluations() const { return evaluations_; }

 private:
  std::uint64_t store_changes() const;

  const banks::RegisterStore& store_;
  const ValueModel& model_;
  Snapshot snapshot_;
  std::uint64_t snapshot_at_ = UINT64_MAX;  // store_changes() when snapshot_ was read
  struct Evaluated {
    std::uint64_t at = UINT64_MAX;  // the bank's changes() when evaluated
    std::vector<Value> values;
  };
  std::array<Evaluated, banks::bank_count> banks_;
  std::uint64_t evaluations_ = 0;
};

}  // namespace unima::values
