#pragma once
// What the services of the bridge share (app::Bridge owns it and loops over them): the
// banks of the running config, swapped whole on a reload, and what lives as long as the
// daemon — the monitor, the state file, the error hold, the publisher to UnimaBUS.

#include <chrono>
#include <functional>
#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "banks/register_space.hpp"
#include "banks/register_store.hpp"
#include "banks/write_path.hpp"
#include "config/config.hpp"
#include "config/register_map.hpp"
#include "io/error_hold.hpp"
#include "io/gateway_request.hpp"
#include "io/state_file.hpp"
#include "modbus/capture.hpp"
#include "monitor/monitor.hpp"
#include "platform/asio.hpp"
#include "unimabus/publisher.hpp"
#include "unimabus/telegram_intake.hpp"
#include "values/value_model.hpp"

namespace unima::io {

/// One config and everything derived from it once: the register store and space, the
/// one write path, the telegram intake, the capture rules, the register map and the
/// value model (SPEC §17).
struct Banks {
  config::Config config;
  std::unique_ptr<banks::RegisterStore> store;
  std::unique_ptr<banks::RegisterSpace> space;
  std::unique_ptr<banks::WritePath> writes;
  std::unique_ptr<unimabus::TelegramIntake> intake;
  std::vector<modbus::CaptureRule> capture_rules;
  std::vector<config::MapRow> register_rows;  // in address order: the page, /api/registers
  values::ValueModel value_model;
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
  std::chrono::steady_clock::time_point started_at = std::chrono::steady_clock::now();
  std::chrono::system_clock::time_point started_utc = std::chrono::system_clock::now();  // the birth's `started`
  /// The whole status document (`unima-bridge status --json`), for who shows it.
  std::function<nlohmann::json()> status;
  /// A TCP client's request for a foreign slave (modbus.gateway, SPEC §14), to the running
  /// master's line; the master service sets it.
  std::function<void(GatewayRequest, GatewayAnswer)> forward_to_line;
  /// A client whose requests went through forward_to_line closed its connection: its
  /// requests still queued for the line leave the queue. Set beside forward_to_line.
  std::function<void(std::uint64_t client)> client_gone_from_line;

  /// `listener` is called, on the loop, after anything the banks read changed (the running
  /// store's content listener, banks::RegisterStore): who publishes northbound learns of a
  /// change when it happens instead of looking every so often. For as long as the runtime.
  void on_banks_changed(std::function<void()> listener) { banks_changed_.push_back(std::move(listener)); }
  /// Points `store`'s content listener at on_banks_changed's listeners (the first banks, and
  /// each reload's before they run).
  void watch_changes(banks::RegisterStore& store);

  const config::Config& config() const { return banks->config; }

 private:
  std::vector<std::function<void()>> banks_changed_;
};

}  // namespace unima::io
