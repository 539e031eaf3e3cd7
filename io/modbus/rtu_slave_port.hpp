#pragma once
// Modbus RTU slave on a serial line (SPEC §3, seed 004 §4.1, §5, §7.1). Answers its own
// address no sooner than 2.5 characters after the request; applies broadcasts (address 0)
// without answering; and listens to the whole bus: a request for another slave is
// Not4Me, paired with that slave's response when one follows, and handed to the foreign
// listener (capture blocks). The decisions are pure: framing modbus::RtuFramer's, whose
// request it is and its answer modbus/slave_session's, the pairing modbus::BusListener's;
// this adapter owns the port (opened by io/modbus/serial_line), the timers and the clock.
//
// A port that cannot be opened or goes away (a USB adapter unplugged) is reopened with
// back-off; the rest of the daemon runs on meanwhile.

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "platform/asio.hpp"
#include "io/handler_guard.hpp"
#include "io/lazy_deadline.hpp"
#include "io/modbus/slave_context.hpp"
#include "modbus/rtu/bus_listener.hpp"
#include "modbus/rtu/rtu_framer.hpp"
#include "modbus/slave_session.hpp"
#include "modbus/rtu/rtu_timing.hpp"
#include "status/line_status.hpp"

namespace unima::io {

class RtuSlavePort {
 public:
  /// A request for another slave or a broadcast, as soon as it is heard (response empty),
  /// and again with the foreign slave's response when one is heard. Whole ADUs, CRC checked.
  using ForeignListener =
      std::function<void(std::span<const std::uint8_t> query, std::span<const std::uint8_t> response)>;

  static constexpr std::chrono::milliseconds first_reopen_delay{200};
  static constexpr std::chrono::milliseconds longest_reopen_delay = config::serial_reopen_longest_delay;
  /// A Not4Me request whose response has not come by then is reported without one.
  static constexpr std::chrono::milliseconds foreign_response_timeout{1000};

  RtuSlavePort(asio::io_context& io, const config::RtuConfig& line, const SlaveContext& context);
  ~RtuSlavePort();
  RtuSlavePort(const RtuSlavePort&) = delete;
  RtuSlavePort& operator=(const RtuSlavePort&) = delete;

  /// Opens the line, or keeps trying with back-off.
  void start();
  void stop();
  void set_context(const SlaveContext& context);
  void set_foreign_listener(ForeignListener listener) { foreign_ = std::move(listener); }
  const config::RtuConfig& line() const { return line_; }
  bool is_open() const { return port_.is_open(); }
  const status::LineCounters& counters() const { return counters_; }
  /// Answers waiting for their turn on the line.
  std::size_t queue_depth() const { return out_.size(); }

 private:
  HandlerGuard::Token guard() const { return guard_.token(); }

  struct Outgoing {
    std::vector<std::uint8_t> bytes;
    modbus::RtuClock::time_point not_before;
  };

  void open();
  void schedule_reopen();
  void lost(const std::string& why);
  void close();
  void read();
  void handle(const std::vector<modbus::RtuFrame>& frames);
  modbus::Served serve(const modbus::RtuFrame& query, modbus::Recipient recipient, std::span<std::uint8_t> response) const;
  void answer(const modbus::RtuFrame& query);
  /// Sends `served`'s answer in `response` to `query` (an RTU ADU) and reports it.
  void reply(std::span<const std::uint8_t> query, const modbus::Served& served, std::span<const std::uint8_t> response,
             modbus::RtuClock::time_point not_before);
  void apply_broadcast(const modbus::RtuFrame& query);
  void heard_foreign_query(const modbus::RtuFrame& query);
  void heard_foreign_response(const modbus::RtuFrame& response);
  void heard_faulty_response(const modbus::RtuFrame& response);
  void flush_foreign_query();
  /// `ours`: the response is the one this port sends (else heard from another slave, or none).
  void report(modbus::TransactionState state, std::span<const std::uint8_t> query,
              std::span<const std::uint8_t> response, bool ours = false) const;
  void send(std::vector<std::uint8_t> adu, modbus::RtuClock::time_point not_before);
  void write_next();
  void release_line_after_sending();

  asio::io_context& io_;
  config::RtuConfig line_;
  SlaveContext context_;
  ForeignListener foreign_;
  modbus::RtuTiming timing_;
  modbus::RtuFramer framer_;
  asio::serial_port port_;
  LazyDeadline silence_;  // at the framer's deadline
  asio::steady_timer reply_timer_;
  asio::steady_timer reopen_timer_;
  modbus::BusListener listener_{foreign_response_timeout};
  LazyDeadline give_up_;  // at listener_.deadline()
  std::array<std::uint8_t, 512> in_{};
  std::deque<Outgoing> out_;
  std::chrono::milliseconds reopen_delay_ = first_reopen_delay;
  status::LineCounters counters_;
  bool sending_ = false;
  bool running_ = false;
  bool failing_ = false;  // the last open failed: log again only when it works
  HandlerGuard guard_;  // invalidated when the line closes
};

}  // namespace unima::io
