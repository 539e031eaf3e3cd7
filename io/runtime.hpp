#pragma once
// What the services of the bridge share (app::Bridge owns it and loops over them): the
// banks of the running config, swapped whole on a reload, and what lives as long as the
// daemon — the monitor, the state file, the error hold, the publisher to UnimaBUS.

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "banks/register_space.hpp"
#include "banks/register_store.hpp"
#include "banks/write_path.hpp"
#include "config/config.hpp"
#include "config/register_map.hpp"
#include "io/config_changes.hpp"
#include "io/error_hold.hpp"
#include "io/gateway_line.hpp"
#include "io/state_file.hpp"
#include "io/store_changes.hpp"
#include "modbus/capture.hpp"
#include "monitor/monitor.hpp"
#include "status/document.hpp"
#include "platform/asio.hpp"
#include "report/deadbands.hpp"
#include "unimabus/publisher.hpp"
#include "unimabus/telegram_intake.hpp"
#include "values/current_values.hpp"
#include "values/value_model.hpp"

namespace unima::io {

/// The capture blocks by the slave line they listen on (SPEC §4, §18).
using CaptureRules = std::map<std::string, std::vector<modbus::CaptureRule>, std::less<>>;

/// One config and everything derived from it once: the register store and space, the
/// one write path, the telegram intake, the capture rules, the register map and the
/// value model (SPEC §17).
struct Banks {
  config::Config config;
  std::unique_ptr<banks::RegisterStore> store;
  std::unique_ptr<banks::RegisterSpace> space;
  std::unique_ptr<banks::WritePath> writes;
  std::unique_ptr<unimabus::TelegramIntake> intake;
  CaptureRules capture_rules;
  std::vector<config::MapRow> register_rows;  // in address order: the page, /api/registers
  values::ValueModel value_model;
  /// The values now, evaluated once per change for all who show or publish them.
  std::unique_ptr<values::CurrentValues> values;
  /// What moves each value must make to count as changed (SPEC §21), for MQTT and Sparkplug.
  report::Deadbands deadbands;
};

/// `config`'s banks; the writes go to `journal` (null: kept nowhere).
std::unique_ptr<Banks> build_banks(config::Config config, banks::WriteJournal* journal);

struct Runtime {
  Runtime(asio::io_context& io, std::unique_ptr<Banks> first);

  asio::io_context& io;
  /// The running config's banks. Services read it at each call, so they follow a reload.
  std::unique_ptr<Banks> banks;
  std::unique_ptr<monitor::Monitor> monitor;
  std::unique_ptr<StateFile> state;  // null without `state.file`
  ErrorHold error_hold;              // C+0x13 bit 15, held 2 s after the last fault
  unimabus::Publisher publisher;     // W, X and the user outputs to the running transport
  StoreChanges changes;              // the running store's changes, for who sends values north
  std::chrono::steady_clock::time_point started_at = std::chrono::steady_clock::now();
  std::chrono::system_clock::time_point started_utc = std::chrono::system_clock::now();  // the birth's `started`
  /// The whole status document (`unima-bridge status --json`, /metrics, the page), for who
  /// shows it.
  std::function<status::Document()> status;
  /// The TCP and TLS ports' way to the running master's line (modbus.gateway, SPEC §14);
  /// the master service attaches its master.
  GatewayLine gateway_line{io};
  /// The one flow of configs from afar (SPEC §19), for the channels that carry them; the
  /// daemon's coordinator sets it, and a bridge without one takes no changes.
  ConfigChanges* config_changes = nullptr;

  const config::Config& config() const { return banks->config; }
};

}  // namespace unima::io
