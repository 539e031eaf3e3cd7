#pragma once
// The bridge as a Modbus master (seed 004 §7.2, SPEC §4, docs/master.md): the poll and send
// blocks, planned into requests, sent by the scheduler over the RTU line or to a TCP
// target, on the daemon's event loop. Polled values go to the user analog outputs; sends
// take their source's value at the moment they go out.
//
// Faults (time-out, bad CRC, exception, short or wrong frame) go to the monitor hook, to
// the fault hook (C+0x13 bit 15 and its 2 s hold) and to the counters. A value stays as
// last read until `stale_after` without a good read, then reads 0x7FFF.
//
// With modbus.gateway (SPEC §14, docs/gateway.md), TCP clients' requests for the foreign
// slaves share the line with the polls: master/gateway decides (whose turn, the cache,
// the time-out, the answer, what each unit's outcome counts as), the scheduler says when
// the line is free, and this moves the bytes. A forwarded request goes once (never
// retried), and each is a monitor line of port `gw` (state Cached when the cache answered
// it); a forwarded fault lights the Error LED as a poll's does.

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "banks/source_ref.hpp"
#include "config/config.hpp"
#include "config/master_setup.hpp"
#include "platform/asio.hpp"
#include "io/gateway_request.hpp"
#include "io/lazy_deadline.hpp"
#include "io/master/master_link.hpp"
#include "master/gateway.hpp"
#include "master/staleness.hpp"
#include "master/master_scheduler.hpp"
#include "modbus/transaction.hpp"
#include "status/line_status.hpp"

namespace unima::io {

/// What the master has done with one device, for the log and `unima-bridge status`.
struct MasterDeviceCounters {
  std::uint64_t requests = 0;    // frames sent, retries and probes included
  std::uint64_t answered = 0;    // good answers
  std::uint64_t timeouts = 0;
  std::uint64_t bad_frames = 0;  // bad CRC or length, too short, wrong function, address or echo
  std::uint64_t exceptions = 0;
  std::uint64_t retries = 0;
  std::uint64_t probes = 0;
  std::uint64_t skipped = 0;     // sends left out: their source was not measured
  bool degraded = false;
};

/// Kept under its old name for the status document's readers.
using GatewayUnitCounters = master::GatewayUnitCounters;

class MasterPort final : public LineGateway, public std::enable_shared_from_this<MasterPort> {
 public:
  struct Hooks {
    /// The value of a send's source now; nullopt while it is not measured (0x7FFF).
    std::function<std::optional<std::uint16_t>(const banks::SourceRef&)> read_source;
    /// User analog output n (1..16) = C+(n-1).
    std::function<void(unsigned output, std::uint16_t value)> set_output;
    /// Any fault: C+0x13 bit 15.
    std::function<void()> on_fault;
    /// Every transaction (the monitor), once answered or timed out. Must not block.
    std::function<void(const modbus::Transaction&)> on_transaction;
    /// A query goes on the line now, before its answer (the Modbus LED, SPEC §8).
    std::function<void(std::chrono::system_clock::time_point)> on_query_sent;
  };

  /// Opens the line of `recipe` (or connects to its TCP target); throws std::runtime_error
  /// when it cannot.
  static std::shared_ptr<MasterPort> create(asio::io_context& io, const config::MasterRecipe& recipe, Hooks hooks);
  ~MasterPort();

  void start();
  void stop();
  /// A reload kept this port (config::same_master_port): its blocks' positions in the file,
  /// which its warnings name, become those of `setup`.
  void take_positions(const config::MasterSetup& setup);

  /// A TCP client's request for a foreign slave (modbus.gateway): queued for the line and
  /// answered once; 0x06 when it could not start within `wait`, 0x0B when the slave did
  /// not answer well.
  void forward(GatewayRequest request, GatewayAnswer answer) override;
  /// A client's connection closed: its requests still queued leave the queue unanswered
  /// (nobody would read the answer). One already on the line runs to its end.
  void client_gone(std::uint64_t client) override;

  std::string describe() const { return link_->describe(); }
  /// False while the line's serial device is lost and being reopened.
  bool line_open() const { return link_->is_open(); }
  const std::map<std::uint8_t, MasterDeviceCounters>& counters() const { return counters_; }
  /// Each unit id a client has asked the gateway for; empty without modbus.gateway.
  const std::map<std::uint8_t, GatewayUnitCounters>& gateway_units() const;
  /// The requests for `unit` waiting for the line now.
  std::size_t queue_depth(std::uint8_t unit) const { return gateway_ ? gateway_->queue_depth(unit) : 0; }
  /// Every client request waiting for the line now.
  std::size_t queue_depth() const { return gateway_ ? gateway_->waiting() : 0; }
  /// The line's frames: each query sent, each answer heard whole, each time-out or bad answer.
  const status::LineCounters& line_counters() const { return line_counters_; }
  const std::optional<config::GatewayConfig>& gateway_config() const { return gateway_config_; }

  MasterPort(asio::io_context& io, config::MasterSetup setup, std::shared_ptr<MasterLink> link, Hooks hooks,
             std::optional<config::GatewayConfig> gateway = std::nullopt);

 private:
  using Clock = master::MasterScheduler::Clock;
  void pump();
  void send(const master::MasterScheduler::Choice& choice);
  void finished(const master::MasterScheduler::Choice& choice, const master::Bytes& pdu,
                std::chrono::system_clock::time_point sent, master::Bytes query, master::Bytes response);
  struct Forwarded {
    GatewayRequest request;
    GatewayAnswer answer;
  };
  void forward_now(const master::GatewayQueue::Request& next, Clock::time_point now);
  void forwarded(const Forwarded& forwarded, Clock::time_point started, std::chrono::system_clock::time_point sent,
                 const master::Bytes& query, const master::Bytes& response);
  /// Answers a read from the cache, after this call; the monitor sees it now.
  void answer_from_cache(Forwarded forwarded, master::Bytes answer);
  /// Answers a forwarded request with `answer`, after this call.
  void answer_later(Forwarded forwarded, master::Bytes answer);
  /// Answers a forwarded request with the gateway's own exception, after this call.
  void refuse(Forwarded forwarded, modbus::ExceptionCode code);
  /// Answers 0x06 to the requests that have waited `wait`, also while a transaction is
  /// under way, and arms the timer for the next.
  void expire_waiting();
  void take_values(const master::PlannedRequest& request, const master::MasterResponse& result, Clock::time_point now);
  void publish(unsigned output, std::uint16_t value);
  void expire_stale_values();

  config::MasterSetup setup_;
  std::shared_ptr<MasterLink> link_;
  Hooks hooks_;
  std::optional<master::MasterScheduler> scheduler_;
  asio::steady_timer wake_timer_;
  std::optional<master::Staleness> staleness_;
  LazyDeadline stale_timer_;  // at staleness_->next_expiry()
  std::map<unsigned, std::uint16_t> published_;
  std::vector<bool> skip_warned_;
  std::map<std::uint8_t, MasterDeviceCounters> counters_;
  status::LineCounters line_counters_;
  void count_on_line(const master::Bytes& query, const master::MasterResponse& result);
  bool in_flight_ = false;
  std::chrono::milliseconds waiting_for_answer_{0};  // the time-out of the transaction on the line
  bool running_ = false;
  asio::any_io_executor executor_;
  std::optional<config::GatewayConfig> gateway_config_;
  std::optional<master::Gateway> gateway_;
  asio::steady_timer expiry_timer_;
  std::map<master::Gateway::Ticket, Forwarded> waiting_;  // queued for the line
  std::optional<Forwarded> on_line_;                       // the forwarded request under way
};

/// One line for the log: "Timeout rtu 01 03 04 24 00 02 85 30 -> -".
std::string describe_master_transaction(const modbus::Transaction& transaction);

}  // namespace unima::io
