#include "io/unimabus/telegram_recorder.hpp"

#include "unimabus/feed_codec.hpp"

namespace unima::io {

TelegramRecorder::TelegramRecorder(const config::RecordConfig& config, std::chrono::steady_clock::time_point origin)
    : config_(config),
      origin_(origin),
      sink_(config.file, config.max_size, config.max_files, monitor::FileAppender::Route::page_cache,
            "unimabus record", "unimabus.record.file") {}

void TelegramRecorder::record(const unimabus::Telegram& telegram, std::chrono::steady_clock::time_point now) {
  const double t = std::chrono::duration<double>(now - origin_).count();
  sink_.write(unimabus::format_recorded(telegram, t));
  sink_.flush();  // a recording is read while it grows (tail -F), and survives a crash
}

}  // namespace unima::io
