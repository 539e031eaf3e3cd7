#include "banks/table_catalog.hpp"

#include <algorithm>
#include <memory>
#include <mutex>

#include "banks/embedded_tables.hpp"

namespace unima::banks {

namespace {

bool is_device_type(std::string_view id) { return id != io_module_table_id && id != bridge_internal_table_id; }

// Parsing all eleven tables costs tens of milliseconds and about a megabyte of short-lived
// YAML nodes, whose holes stay in the heap between the tables that live on. A daemon
// needs three or four of them, so the catalog knows every table by its head (id and
// aliases) and parses a table's registers when it is first asked for.
class Catalog {
 public:
  Catalog() {
    for (const auto& embedded : embedded_tables()) {
      Entry entry;
      entry.origin = std::string("banks/tables/").append(embedded.file_name);
      entry.text = embedded.yaml_text;
      entry.head = parse_device_table_head(entry.text, entry.origin);
      entries_.push_back(std::move(entry));
    }
    std::sort(entries_.begin(), entries_.end(), [](const auto& a, const auto& b) { return a.head.id < b.head.id; });
  }

  /// Any table, by its id.
  const DeviceTable* table(std::string_view id) {
    for (auto& entry : entries_)
      if (entry.head.id == id) return &parsed(entry);
    return nullptr;
  }

  /// A D_N device type, by its id or an alias.
  const DeviceTable* device_type(std::string_view id) {
    for (auto& entry : entries_) {
      const auto& aliases = entry.head.aliases;
      if (is_device_type(entry.head.id) &&
          (entry.head.id == id || std::find(aliases.begin(), aliases.end(), id) != aliases.end()))
        return &parsed(entry);
    }
    return nullptr;
  }

  std::vector<const DeviceTable*> all() {
    std::vector<const DeviceTable*> tables;
    for (auto& entry : entries_) tables.push_back(&parsed(entry));
    return tables;
  }

  std::vector<std::string_view> device_type_ids() const {
    std::vector<std::string_view> ids;
    for (const auto& entry : entries_)
      if (is_device_type(entry.head.id)) ids.push_back(entry.head.id);
    return ids;
  }

 private:
  struct Entry {
    std::string origin;
    std::string_view text;
    DeviceTableHead head;
    std::unique_ptr<const DeviceTable> table;  // parsed on first use
  };

  // Config loads may run on more than one thread (tests do), so parsing takes the lock;
  // a parsed table never moves or changes.
  const DeviceTable& parsed(Entry& entry) {
    std::lock_guard lock(mutex_);
    if (!entry.table) entry.table = std::make_unique<const DeviceTable>(parse_device_table(entry.text, entry.origin));
    return *entry.table;
  }

  std::vector<Entry> entries_;
  std::mutex mutex_;
};

Catalog& catalog() {
  static Catalog instance;
  return instance;
}

}  // namespace

std::vector<const DeviceTable*> all_tables() { return catalog().all(); }

const DeviceTable* find_device_type(std::string_view id) { return catalog().device_type(id); }

std::vector<std::string_view> device_type_ids() { return catalog().device_type_ids(); }

const DeviceTable* io_module_table() { return catalog().table(io_module_table_id); }
const DeviceTable* bridge_internal_table() { return catalog().table(bridge_internal_table_id); }

}  // namespace unima::banks
