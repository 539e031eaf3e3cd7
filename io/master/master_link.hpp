#pragma once
// The line a Modbus master drives: RTU on a serial port, or TCP to one target. A link
// sends one request and hands back the bytes heard, as on the wire; whether they are a
// good answer is decided by master/master_codec. One transaction at a time.
//
// No library thread here: libmodbus's master calls block, so they would need a thread of
// their own posting back to the loop, and its modbus_receive_confirmation drops the bytes
// of a frame it rejects (which the monitor must show). The links are asynchronous Asio
// I/O on the daemon's one event loop instead (docs/master.md).

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>

#include "master/master_codec.hpp"

namespace unima::io {

/// Held by shared_ptr: the handlers of its I/O keep it alive until they have run.
class MasterLink : public std::enable_shared_from_this<MasterLink> {
 public:
  /// The request ADU as sent, and what was heard in answer (empty: nothing).
  using Done = std::function<void(master::Bytes query, master::Bytes response)>;

  virtual ~MasterLink() = default;
  /// Sends `pdu` to `unit` and calls `done` once: with the response, or with what came
  /// within `timeout` (an empty response when nothing did).
  virtual void transact(std::uint8_t unit, const master::Bytes& pdu, std::chrono::milliseconds timeout, Done done) = 0;
  /// Stops everything under way; `done` is not called after this.
  virtual void close() = 0;
  virtual master::MasterResponse check(std::span<const std::uint8_t> response, std::uint8_t unit,
                                       std::span<const std::uint8_t> request_pdu) const = 0;
  /// "rtu /dev/ttyUSB0 38400 8N1" or "tcp 10.0.0.5:502".
  virtual std::string describe() const = 0;
  /// The peer for the monitor's Transaction: "host:port" of a TCP target, empty for RTU.
  virtual std::string peer() const = 0;
  /// False while the serial device is lost and being reopened (the status' `open`).
  virtual bool is_open() const { return true; }
  /// Called when a lost device has been opened again; null: nobody is told.
  void on_reopened(std::function<void()> reopened) { reopened_ = std::move(reopened); }

 protected:
  std::function<void()> reopened_;
};

}  // namespace unima::io
