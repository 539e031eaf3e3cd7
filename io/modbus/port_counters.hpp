#pragma once
// A Modbus port's line in the status document's "ports": its transactions by state.

#include <string>

#include <nlohmann/json.hpp>

#include "modbus/transaction.hpp"
#include "monitor/monitor_line.hpp"

namespace unima::io {

inline nlohmann::json port_counters(const char* name, const modbus::TransactionCounters& c) {
  nlohmann::json j;
  j["port"] = name;
  j["transactions"] = c.transactions;
  for (std::size_t i = 0; i < modbus::transaction_state_count; ++i) {
    const auto state = static_cast<modbus::TransactionState>(i);
    j[std::string(monitor::state_name(state))] = c.of(state);
  }
  return j;
}

}  // namespace unima::io
