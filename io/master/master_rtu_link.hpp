#pragma once
// The master's RTU line (SPEC §3, Modbus over Serial Line V1.02 §2.5): a serial port in
// raw mode, opened as the slave port's is (io/modbus/serial_line). A response ends when its length, known from its first bytes, is there; a
// frame whose length cannot be known (wrong function, garbage) or that stops short ends
// at a silence of t3.5 — stretched to `late_byte_tolerance`, because USB adapters deliver
// bytes in bursts with gaps of their latency timer.
//
// The device must open when the config is applied (start, reload): a wrong path is caught
// at once. Lost later (a USB adapter unplugged, a read or write that fails), it is reopened
// as the slave line's is, every 5 s at most; meanwhile each transaction ends as a time-out
// without touching the line, so the master's scheduler and gateway go on as with a silent
// slave and no other line waits for this one.

#include <chrono>
#include <memory>

#include "config/config.hpp"
#include "platform/asio.hpp"
#include "io/master/master_link.hpp"
#include "master/master_plan.hpp"

namespace unima::io {

class MasterRtuLink final : public MasterLink {
 public:
  static constexpr std::chrono::milliseconds late_byte_tolerance{20};

  /// Opens and sets up the serial line; throws std::runtime_error naming the device.
  MasterRtuLink(asio::io_context& io, const config::RtuConfig& line);
  ~MasterRtuLink() override;

  void transact(std::uint8_t unit, const master::Bytes& pdu, std::chrono::milliseconds timeout, Done done) override;
  void close() override;
  master::MasterResponse check(std::span<const std::uint8_t> response, std::uint8_t unit,
                               std::span<const std::uint8_t> request_pdu) const override;
  std::string describe() const override;
  std::string peer() const override { return {}; }
  bool is_open() const override { return open_; }

 private:
  void read(unsigned generation);
  void finish(unsigned generation);
  void set_rts(bool on);
  void lost(const std::string& why);
  void schedule_reopen();

  config::RtuConfig line_;
  modbus::RtuTiming timing_;
  asio::serial_port port_;
  asio::steady_timer deadline_;
  asio::steady_timer silence_;
  asio::steady_timer rts_timer_;
  asio::steady_timer reopen_timer_;
  std::chrono::milliseconds reopen_delay_{200};
  bool open_ = true;
  bool closed_ = false;  // by close(): never reopened
  std::array<std::uint8_t, 512> chunk_{};
  master::Bytes query_;
  master::Bytes response_;
  std::uint8_t function_ = 0;
  Done done_;
  unsigned generation_ = 0;  // handlers of an earlier transaction see a different number
  bool rts_warned_ = false;
};

}  // namespace unima::io
