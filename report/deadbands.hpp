#pragma once
// The deadband of every reported value (SPEC §21), from `report.deadband` over the value
// model: each value its own key's, else `default`. A bit word, a bit and a text have
// none — their every change counts — so `default` leaves them alone, and a key that names
// one is an error, as is a key that names no value of its bank (at the key's
// file:line:column, a config::ConfigError). Built once per config. Pure.

#include <array>
#include <span>
#include <vector>

#include "config/config.hpp"
#include "values/value_model.hpp"

namespace unima::report {

class Deadbands {
 public:
  /// Every deadband 0: every change counts.
  Deadbands() = default;
  /// Throws config::ConfigError for a key the model has no number value for.
  Deadbands(const config::ReportConfig& report, const values::ValueModel& model);

  /// `bank`'s deadbands by the index of their value in its layout; empty for a bank
  /// without values (or a default-built Deadbands): 0 for all.
  std::span<const double> of(banks::BankId bank) const { return banks_[banks::index_of(bank)]; }

 private:
  std::array<std::vector<double>, banks::bank_count> banks_;
};

/// Whether a deadband means anything for `def`: a number that is not a bit word or a bit field.
bool takes_deadband(const values::ValueDef& def);

}  // namespace unima::report
