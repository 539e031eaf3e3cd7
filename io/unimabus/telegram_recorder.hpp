#pragma once
// `unimabus.record` (SPEC §6): every telegram the bridge receives, whatever the transport,
// appended to a size-rotated file in the replay format, `t` counted from the daemon's
// start. Each telegram is one whole line, written before the next turn of the loop (a
// write(2) into the page cache: telegrams come at most a few thousand a second, far below
// what needed the monitor's writer thread).

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include "config/config.hpp"
#include "monitor/monitor_sinks.hpp"
#include "unimabus/telegram_intake.hpp"

namespace unima::io {

class TelegramRecorder final : public unimabus::TelegramRecording {
 public:
  /// Opens (creating the directory); throws std::runtime_error naming the key and the file
  /// (a symbolic link is refused, never followed).
  TelegramRecorder(const config::RecordConfig& config, std::chrono::steady_clock::time_point origin);

  void record(const unimabus::Telegram& telegram, std::chrono::steady_clock::time_point now) override;
  const config::RecordConfig& config() const { return config_; }

 private:
  config::RecordConfig config_;
  std::chrono::steady_clock::time_point origin_;
  monitor::RotatingFileSink sink_;
};

}  // namespace unima::io
