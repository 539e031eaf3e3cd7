#include "banks/table_catalog.hpp"

#include <algorithm>

#include "banks/embedded_tables.hpp"

namespace unima::banks {

const std::vector<DeviceTable>& all_tables() {
  static const std::vector<DeviceTable> tables = [] {
    std::vector<DeviceTable> parsed;
    for (const auto& embedded : embedded_tables())
      parsed.push_back(parse_device_table(embedded.yaml_text, std::string("banks/tables/").append(embedded.file_name)));
    std::sort(parsed.begin(), parsed.end(), [](const auto& a, const auto& b) { return a.id < b.id; });
    return parsed;
  }();
  return tables;
}

namespace {
const DeviceTable* find_table(std::string_view id) {
  for (const auto& table : all_tables())
    if (table.id == id) return &table;
  return nullptr;
}
bool is_device_type(const DeviceTable& table) {
  return table.id != io_module_table_id && table.id != bridge_internal_table_id;
}
}  // namespace

const DeviceTable* find_device_type(std::string_view id) {
  for (const auto& table : all_tables()) {
    if (!is_device_type(table)) continue;
    if (table.id == id || std::find(table.aliases.begin(), table.aliases.end(), id) != table.aliases.end())
      return &table;
  }
  return nullptr;
}

std::vector<std::string_view> device_type_ids() {
  std::vector<std::string_view> ids;
  for (const auto& table : all_tables())
    if (is_device_type(table)) ids.push_back(table.id);
  return ids;
}

const DeviceTable* io_module_table() { return find_table(io_module_table_id); }
const DeviceTable* bridge_internal_table() { return find_table(bridge_internal_table_id); }

}  // namespace unima::banks
