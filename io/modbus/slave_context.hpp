#pragma once
// What a Modbus slave port serves. The bridge replaces it on reload; ports read it at
// every request, so a reload never drops a connection.

#include <cstdint>
#include <functional>
#include <memory>

#include "config/config.hpp"
#include "io/gateway_request.hpp"
#include "modbus/register_model.hpp"
#include "modbus/request_handler.hpp"
#include "modbus/transaction.hpp"

namespace unima::io {

class StateFile;
struct Runtime;

struct SlaveContext {
  modbus::RegisterModel* registers = nullptr;
  modbus::HandlerOptions options;
  std::uint8_t unit_id = 1;
  /// When set, a request that wrote takes effect and is answered only once the state file
  /// holds what it wrote (SPEC §10); when that failed, nothing changed and it is answered
  /// exception 04 (modbus::refuse_unkept_write).
  StateFile* state = nullptr;
  /// Called on every fault a port sees (exception sent, bad frame): C+0x13 bit 15.
  std::function<void()> on_fault;
  /// Called after every transaction, when set (the monitor, indicators). Must not block.
  std::function<void(const modbus::Transaction&)> on_transaction;
  /// Every master line's gateway (SPEC §14, §18), a copy that lives as long as this
  /// context: the unit ids the TCP and TLS ports forward, each with its line's settings;
  /// null without a gateway.
  std::shared_ptr<const config::GatewayRoutes> gateway;
  /// The way to the lines (io::GatewayLine: to the unit's line, 0x0B while none runs);
  /// null without a gateway.
  LineGateway* line = nullptr;
  /// config::writes_frozen: no port takes a write, forwarded ones included.
  bool writes_frozen = false;
};

/// The running banks served as the config says (the write path, the extensions, the own
/// unit id), faults to the error hold, transactions to the monitor; a TCP slave's
/// maximum read (an RTU port sets its own).
SlaveContext slave_context(Runtime& runtime);

}  // namespace unima::io
