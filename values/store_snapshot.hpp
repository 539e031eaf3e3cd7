#pragma once
// The registers of a running bridge's store as the value model reads them: what a
// Modbus master reads, except that a register without a value is nullopt rather than its
// stand-in (0x7FFF, 0), so that a value can say why it has none.

#include "banks/register_store.hpp"
#include "values/value_model.hpp"

namespace unima::values {

Snapshot snapshot_of(const banks::RegisterStore& store);

}  // namespace unima::values
