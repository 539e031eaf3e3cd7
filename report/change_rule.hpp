#pragma once
// When a value counts as changed (SPEC §21): when it differs from the value last
// *published* by more than its deadband, absolutely, in its unit. A change to or from null,
// and any change of a boolean or a text, always counts; a value that stays null (only why
// changed: not measured, then off-line) does not — a document shows the same null. The
// one rule MQTT's documents and Sparkplug's DDATA both ask. Pure.

#include "values/value_model.hpp"

namespace unima::report {

/// Whether `now` counts as changed from `published`; `deadband` ≥ 0 (0: any change).
bool counts_as_changed(const values::Value& published, const values::Value& now, double deadband);

}  // namespace unima::report
