#pragma once
// The bridge's banks as the daemon builds them from a config (io::build_banks), for
// the targets that serve Modbus requests or route telegrams: the register store, the
// register space behind the request handler, the telegram router.
//
// The config is one of config/examples/, loaded once per process. The banks are built
// afresh for every input, so what an input does never depends on the inputs before it
// and a crash file reproduces on its own.

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "banks/write_path.hpp"
#include "banks/register_space.hpp"
#include "banks/register_store.hpp"
#include "config/config.hpp"
#include "unimabus/telegram_router.hpp"

namespace unima::fuzz {

/// config/examples/<file> of the source tree the target was built from.
inline config::Config load_example(const std::string& file) {
  return config::load_file(std::string(UNIMA_SOURCE_DIR) + "/config/examples/" + file);
}

/// An example config and its address map, loaded once per process: the same for every
/// input, and the map takes longer to build than the rest.
struct Example {
  config::Config config;
  banks::AddressMap map;
};
inline const Example& example(const std::string& file) {
  static std::map<std::string, Example> loaded;
  auto found = loaded.find(file);
  if (found == loaded.end()) {
    auto config = load_example(file);
    auto map = config::address_map(config);
    found = loaded.emplace(file, Example{std::move(config), std::move(map)}).first;
  }
  return found->second;
}

/// Which D_N sits at which UnimaBUS address; io/runtime.cpp's device_addresses, which is
/// private to the bridge.
inline std::vector<std::pair<banks::BankId, std::uint8_t>> device_addresses(const config::Config& config) {
  std::vector<std::pair<banks::BankId, std::uint8_t>> addresses;
  for (unsigned n = 1; n <= 4; ++n)
    if (const auto& device = config.devices[n - 1]) addresses.emplace_back(banks::device_bank(n), device->address);
  return addresses;
}

class BridgeBanks {
 public:
  /// `map` is config::address_map(config).
  BridgeBanks(const config::Config& config, const banks::AddressMap& map)
      : store(config::bank_shapes(config)),
        space(map, store, banks::AccessRules{config.modbus.readable_write_banks}),
        model(space, nullptr),
        router(unimabus::standard_routes(config.unimabus.address, store, device_addresses(config)), store) {
    store.set_mapping(config.mapping);
  }
  explicit BridgeBanks(const Example& example) : BridgeBanks(example.config, example.map) {}

  /// Every D_N and S_N on-line and carrying values, so that reads take the path of
  /// measured values (and bank A's conversion to tenths) and not only the off-line one.
  void bring_plant_online() {
    for (const auto bank : banks::all_banks) {
      if (!(banks::is_device_bank(bank) || banks::is_module_bank(bank)) || !store.exists(bank)) continue;
      std::vector<std::uint16_t> values(store.filled_length(bank));  // past a table nothing is stored
      for (std::size_t i = 0; i < values.size(); ++i)  // small, negative, "not measured", large
        values[i] = static_cast<std::uint16_t>(i * 0x1111u + banks::index_of(bank) * 7u);
      store.store_telegram(bank, 0, values);
      store.set_online(bank, true);
    }
  }

  banks::RegisterStore store;
  banks::RegisterSpace space;
  banks::WritePath model;
  unimabus::TelegramRouter router;
};

}  // namespace unima::fuzz
