#pragma once
// Puts telegram values into the banks (SPEC §6): D_N by device type and address (slot 0),
// S_N by slot N at the bridge's own address.

#include <cstdint>
#include <string>
#include <vector>

#include "banks/register_store.hpp"
#include "unimabus/telegram.hpp"

namespace unima::unimabus {

struct Route {
  banks::BankId bank;
  std::uint8_t address;
  std::uint8_t slot;
  const banks::DeviceTable* table = nullptr;  // D_N: its device type
};

/// The routes of a config: each configured D_N, and S1..S7 at the bridge's address.
std::vector<Route> standard_routes(std::uint8_t bridge_address, const banks::RegisterStore& store,
                                   const std::vector<std::pair<banks::BankId, std::uint8_t>>& device_addresses);

class TelegramRouter {
 public:
  TelegramRouter(std::vector<Route> routes, banks::RegisterStore& store) : routes_(std::move(routes)), store_(store) {}

  struct Outcome {
    std::vector<banks::BankId> updated;  // banks that took the values (their device was heard)
    std::string error;                   // non-empty when the telegram was refused
    bool ignored = false;                // it was for no configured bank: another device's
  };
  /// A telegram is taken whole by the bank of its device or refused (values past the end
  /// of its table). One naming its device type goes to the D_N of that type at its
  /// address; one that does not name it, to the one D_N at its address, and is refused
  /// when several D_N share that address. One for no bank at all is ignored.
  Outcome apply(const Telegram& telegram);

 private:
  std::vector<Route> routes_;
  banks::RegisterStore& store_;
};

}  // namespace unima::unimabus
