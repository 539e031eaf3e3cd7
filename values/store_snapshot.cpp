#include "values/store_snapshot.hpp"

namespace unima::values {

Snapshot snapshot_of(const banks::RegisterStore& store) {
  Snapshot snapshot;
  for (const auto bank : banks::all_banks) {
    if (!store.exists(bank)) continue;
    const bool station = banks::is_device_bank(bank) || banks::is_module_bank(bank);
    auto& reading = snapshot[index_of(bank)];
    reading.online = !station || store.online(bank);
    reading.registers.resize(store.length(bank));
    for (std::uint16_t offset = 0; offset < store.length(bank); ++offset) {
      const bool held = station                       ? store.measured(bank, offset)
                        : banks::is_write_bank(bank) ? store.written(bank, offset)
                                                     : true;
      if (held) reading.registers[offset] = store.read(bank, offset);
    }
  }
  return snapshot;
}

}  // namespace unima::values
