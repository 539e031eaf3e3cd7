#include "unimabus/telegram_router.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace unima::unimabus {

std::vector<Route> standard_routes(std::uint8_t bridge_address, const banks::RegisterStore& store,
                                   const std::vector<std::pair<banks::BankId, std::uint8_t>>& device_addresses) {
  std::vector<Route> routes;
  for (const auto& [bank, address] : device_addresses)
    if (store.exists(bank)) routes.push_back({bank, address, 0, store.table(bank)});
  for (unsigned n = 1; n <= 7; ++n) routes.push_back({banks::module_bank(n), bridge_address, static_cast<std::uint8_t>(n)});
  return routes;
}

TelegramRouter::Outcome TelegramRouter::apply(const Telegram& telegram) {
  Outcome outcome;
  std::vector<const Route*> matches;
  for (const auto& route : routes_)
    if (route.address == telegram.address && route.slot == telegram.slot &&
        (telegram.device == nullptr || route.table == telegram.device))
      matches.push_back(&route);
  if (matches.empty()) {
    outcome.ignored = true;
    return outcome;
  }
  // A config never gives two D_N one type and address, so more than one match means the
  // telegram did not say which of the unit's components it comes from.
  if (matches.size() > 1) {
    std::vector<std::string> names;
    for (const auto* route : matches)
      names.push_back(fmt::format("{} ({})", banks::bank_name(route->bank), route->table ? route->table->id : "?"));
    outcome.error = fmt::format("address {} holds {}: name the device, e.g. \"device\":\"{}\"", telegram.address,
                                fmt::join(names, ", "), matches.back()->table ? matches.back()->table->id : "?");
    return outcome;
  }
  const Route& route = *matches.front();
  if (!store_.store_telegram(route.bank, telegram.offset, telegram.values)) {
    const auto* table = store_.table(route.bank);
    outcome.error = fmt::format("registers 0x{:02X}..0x{:02X} run past the end of bank {} ({}{} registers)",
                                telegram.offset, telegram.offset + telegram.values.size() - 1,
                                banks::bank_name(route.bank), table ? table->id + ": " : "",
                                store_.filled_length(route.bank));
    return outcome;
  }
  outcome.updated.push_back(route.bank);
  return outcome;
}

}  // namespace unima::unimabus
