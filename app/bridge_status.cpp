// Bridge::status_document: what the seed's front panel and monitor LEDs show (seed 004
// §8, SPEC §8 `unima-bridge status`) plus the counters, as one JSON document.

#include <unistd.h>

#include <algorithm>

#include <nlohmann/json.hpp>

#include "banks/register_space.hpp"
#include "banks/table_catalog.hpp"
#include "app/bridge.hpp"
#include "app/bridge_core.hpp"
#include "monitor/monitor_line.hpp"
#include "platform/process_memory.hpp"

namespace unima::app {

namespace {

using SteadyClock = std::chrono::steady_clock;
using banks::BankId;

// An LED that blinks on traffic reads "active" while the last frame is this recent.
constexpr auto activity_window = std::chrono::seconds(1);

// How long ago, never negative (the wall clock may have been set back since).
template <typename Clock>
std::optional<std::chrono::milliseconds> age(const std::optional<typename Clock::time_point>& last) {
  if (!last) return std::nullopt;
  return std::max(std::chrono::milliseconds(0),
                  std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - *last));
}

nlohmann::json activity(std::optional<std::chrono::milliseconds> age) {
  nlohmann::json j;
  j["active"] = age && *age <= activity_window;
  j["last_ms_ago"] = age ? nlohmann::json(age->count()) : nlohmann::json(nullptr);
  return j;
}

nlohmann::json port_counters(const char* name, const modbus::TransactionCounters& c) {
  nlohmann::json j;
  j["port"] = name;
  j["transactions"] = c.transactions;
  for (std::size_t i = 0; i < modbus::transaction_state_count; ++i) {
    const auto state = static_cast<modbus::TransactionState>(i);
    j[std::string(monitor::state_name(state))] = c.of(state);
  }
  return j;
}

}  // namespace

std::string Bridge::status_document() const {
  return status_json().dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

nlohmann::json Bridge::status_json() const {
  const auto now = SteadyClock::now();
  const auto& config = core_->config;
  const auto& store = *core_->store;
  const auto online_bits = store.online_bits();

  nlohmann::json doc;
  doc["pid"] = ::getpid();
  doc["config"] = config.file;
  doc["uptime_s"] = std::chrono::duration_cast<std::chrono::seconds>(now - started_at_).count();
  if (const auto rss = platform::resident_bytes()) doc["rss_bytes"] = *rss;
  doc["mode"] = config.modbus.mode == config::ModbusMode::master ? "master" : "slave";
  doc["modbus_address"] = config.modbus.address;
  doc["unimabus_address"] = config.unimabus.address;
  doc["error"] = (online_bits >> banks::c_bank::modbus_error_bit & 1) != 0;
  doc["online_bits"] = online_bits;
  doc["modbus"] = activity(age<std::chrono::system_clock>(monitor_->last_transaction()));
  doc["unimabus"] = activity(age<SteadyClock>(core_->intake->last_telegram()));
  doc["unimabus"]["transport"] = config::transport_name(config.unimabus.transport);
  doc["unimabus"]["recording"] =
      config.unimabus.record.file.empty() ? nlohmann::json(nullptr) : nlohmann::json(config.unimabus.record.file);
  doc["unimabus"]["telegrams_ignored"] = core_->intake->counts().ignored;
  doc["unimabus"]["telegrams_refused"] = core_->intake->counts().refused;
  if (const auto clients = transport_ ? transport_->clients() : std::nullopt) doc["unimabus"]["clients"] = *clients;

  doc["devices"] = nlohmann::json::array();
  for (unsigned n = 1; n <= 4; ++n) {
    const auto bank = banks::device_bank(n);
    nlohmann::json d;
    d["bank"] = banks::bank_name(bank);
    if (const auto& device = config.devices[n - 1]) {
      d["type"] = device->table->id;
      d["address"] = device->address;
      d["online"] = store.online(bank);
      d["telegrams"] = core_->intake->counts().taken[banks::index_of(bank)];
    } else {
      d["type"] = nullptr;
      d["online"] = false;
    }
    doc["devices"].push_back(d);
  }
  doc["modules"] = nlohmann::json::array();
  for (unsigned n = 1; n <= 7; ++n)
    doc["modules"].push_back(nlohmann::json{{"bank", banks::bank_name(banks::module_bank(n))},
                                            {"slot", n},
                                            {"online", store.online(banks::module_bank(n))},
                                            {"telegrams", core_->intake->counts().taken[banks::index_of(banks::module_bank(n))]}});

  doc["indicators"] = nlohmann::json::array();
  const auto& indicators = monitor_->indicators();
  for (std::size_t i = 0; i < indicators.size(); ++i) {
    nlohmann::json j;
    j["address"] = indicators.spec(i).address;
    j["register"] = indicators.spec(i).reg;
    if (const auto& reading = indicators.reading(i)) {
      std::string time;
      monitor::append_utc_time(time, reading->time);
      j["value"] = reading->value;
      j["access"] = reading->access == modbus::CaptureAccess::write ? "write" : "read";
      j["time"] = time;
    } else {
      j["value"] = nullptr;
      j["access"] = nullptr;
      j["time"] = nullptr;
    }
    doc["indicators"].push_back(j);
  }

  // A port is listed while it is configured or has seen traffic (RTU and master ports
  // count through the same hook).
  doc["ports"] = nlohmann::json::array();
  const auto& tcp_counts = monitor_->counters(modbus::PortKind::tcp);
  if (tcp_ || tcp_counts.transactions > 0) {
    auto j = port_counters("tcp", tcp_counts);
    if (tcp_) {
      j["listen"] = tcp_->options().listen + ":" + std::to_string(tcp_->port());
      j["clients"] = tcp_->client_count();
    }
    doc["ports"].push_back(j);
  }
  const auto& tls_counts = monitor_->counters(modbus::PortKind::tls);
  if (tls_ || tls_counts.transactions > 0) {
    auto j = port_counters("tls", tls_counts);
    if (tls_) {
      j["listen"] = tls_->options().listen + ":" + std::to_string(tls_->port());
      j["clients"] = tls_->client_count();
    }
    doc["ports"].push_back(j);
  }
  for (const auto& [kind, name] : {std::pair{modbus::PortKind::rtu, "rtu"}, std::pair{modbus::PortKind::master, "master"}})
    if (monitor_->counters(kind).transactions > 0) doc["ports"].push_back(port_counters(name, monitor_->counters(kind)));

  if (master_) {
    doc["master"] = nlohmann::json::array();
    for (const auto& [device, c] : master_->counters())
      doc["master"].push_back({{"device", device},      {"requests", c.requests},     {"answered", c.answered},
                               {"timeouts", c.timeouts}, {"exceptions", c.exceptions}, {"bad_frames", c.bad_frames},
                               {"retries", c.retries}});
  }

  const auto& m = monitor_->config();
  nlohmann::json monitor;
  monitor["file"] = m.file.empty() ? nlohmann::json(nullptr) : nlohmann::json(m.file);
  monitor["stdout"] = m.to_stdout;
  monitor["format"] = m.format == monitor::MonitorFormat::json ? "json" : "text";
  monitor["filter"] = monitor_->filter().describe();
  monitor["queue"] = m.queue;
  monitor["written"] = monitor_->written();
  monitor["dropped"] = monitor_->dropped();
  doc["monitor"] = monitor;

  nlohmann::json state;
  if (state_) {
    const auto counters = state_->counters();
    state["file"] = state_->path().string();
    state["records"] = counters.records;
    state["syncs"] = counters.syncs;
    state["failures"] = counters.failures;
  } else {
    state["file"] = nullptr;
  }
  doc["state"] = state;

  if (mqtt_) {
    const auto& c = mqtt_->counters();
    nlohmann::json mqtt{{"broker", config.mqtt->broker},     {"client_id", config.mqtt->client_id},
                        {"topic", config.mqtt->topic},       {"connected", mqtt_->connected()},
                        {"connections", c.connections},      {"drops", c.drops},
                        {"published", c.published}};
    if (const auto since = mqtt_->connected_since()) {
      std::string time;
      monitor::append_utc_time(time, *since);
      mqtt["since"] = time;
    } else {
      mqtt["since"] = nullptr;
    }
    mqtt["last_error"] = mqtt_->last_error().empty() ? nlohmann::json(nullptr) : nlohmann::json(mqtt_->last_error());
    doc["mqtt"] = mqtt;
  }
  return doc;
}

}  // namespace unima::app
