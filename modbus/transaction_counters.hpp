#pragma once
// Per-port counts of transactions by state, for `unima-bridge status`. Pure.

#include <array>
#include <cstdint>

#include "modbus/transaction.hpp"

namespace unima::modbus {

inline constexpr std::size_t transaction_state_count = 8;

struct TransactionCounters {
  std::uint64_t transactions = 0;
  std::array<std::uint64_t, transaction_state_count> by_state{};

  void count(TransactionState state) {
    ++transactions;
    ++by_state[static_cast<std::size_t>(state)];
  }
  std::uint64_t of(TransactionState state) const { return by_state[static_cast<std::size_t>(state)]; }
};

}  // namespace unima::modbus
