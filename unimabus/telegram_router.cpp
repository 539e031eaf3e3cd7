#include "unimabus/telegram_router.hpp"

#include <fmt/format.h>

namespace unima::unimabus {

std::vector<Route> standard_routes(std::uint8_t bridge_address, const banks::RegisterStore& store,
                                   const std::vector<std::pair<banks::BankId, std::uint8_t>>& device_addresses) {
  std::vector<Route> routes;
  for (const auto& [bank, address] : device_addresses)
    if (store.exists(bank)) routes.push_back({bank, address, 0});
  for (unsigned n = 1; n <= 7; ++n) routes.push_back({banks::module_bank(n), bridge_address, static_cast<std::uint8_t>(n)});
  return routes;
}

TelegramRouter::Outcome TelegramRouter::apply(const Telegram& telegram) {
  Outcome outcome;
  for (const auto& route : routes_) {
    if (route.address != telegram.address || route.slot != telegram.slot) continue;
    const std::size_t length = store_.length(route.bank);
    if (telegram.offset + telegram.values.size() > length) {
      if (!outcome.error.empty()) outcome.error += "; ";
      outcome.error += fmt::format("registers 0x{:02X}..0x{:02X} run past the end of bank {} ({} registers)",
                                   telegram.offset, telegram.offset + telegram.values.size() - 1,
                                   banks::bank_name(route.bank), length);
      continue;
    }
    store_.store_telegram(route.bank, telegram.offset, telegram.values);
    outcome.updated.push_back(route.bank);
  }
  return outcome;
}

}  // namespace unima::unimabus
