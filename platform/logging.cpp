#include "platform/logging.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <memory>

#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "platform/journal_stream.hpp"
#include "platform/log_text.hpp"

namespace unima::platform {

namespace {

bool stderr_is_journal() {
  const char* journal_stream = std::getenv("JOURNAL_STREAM");
  struct stat stderr_stat {};
  if (journal_stream == nullptr || ::fstat(STDERR_FILENO, &stderr_stat) != 0) return false;
  return is_journal_stream(journal_stream, stderr_stat.st_dev, stderr_stat.st_ino);
}

/// The %* flag: the message's sd-daemon priority prefix.
class JournalPriorityFlag final : public spdlog::custom_flag_formatter {
 public:
  void format(const spdlog::details::log_msg& msg, const std::tm&, spdlog::memory_buf_t& dest) override {
    const auto prefix = journal_priority_prefix(msg.level);
    dest.append(prefix.data(), prefix.data() + prefix.size());
  }
  std::unique_ptr<custom_flag_formatter> clone() const override { return std::make_unique<JournalPriorityFlag>(); }
};

/// The %V flag: the message with its control characters escaped (platform/log_text). Text
/// from outside is escaped where it is logged (log_safe, the peer warnings); this is the
/// last guard, so that a call that forgot still writes one line — for journald, a newline
/// would even start an entry of its own, without the priority prefix.
class EscapedMessageFlag final : public spdlog::custom_flag_formatter {
 public:
  void format(const spdlog::details::log_msg& msg, const std::tm&, spdlog::memory_buf_t& dest) override {
    const std::string_view text(msg.payload.data(), msg.payload.size());
    std::size_t clean = 0;  // the run of bytes since the last escape, appended at once
    for (std::size_t i = 0; i < text.size(); ++i) {
      const auto byte = static_cast<unsigned char>(text[i]);
      if (!is_control(byte)) continue;
      dest.append(text.data() + clean, text.data() + i);
      char escape[max_escape];
      dest.append(escape, escape_byte(escape, byte));
      clean = i + 1;
    }
    dest.append(text.data() + clean, text.data() + text.size());
  }
  std::unique_ptr<custom_flag_formatter> clone() const override { return std::make_unique<EscapedMessageFlag>(); }
};

}  // namespace

std::unique_ptr<spdlog::formatter> log_formatter(bool to_journal) {
  auto formatter = std::make_unique<spdlog::pattern_formatter>();
  formatter->add_flag<EscapedMessageFlag>('V');
  // journald stamps the time and takes the priority from the prefix: the line carries neither.
  if (to_journal) formatter->add_flag<JournalPriorityFlag>('*').set_pattern("%*%V");
  else formatter->set_pattern("%Y-%m-%dT%H:%M:%S.%e %^%l%$ %V");
  return formatter;
}

void setup_logging(const std::string& level) {
  auto logger = spdlog::stderr_color_mt("unima-bridged");
  spdlog::set_default_logger(logger);
  spdlog::set_formatter(log_formatter(stderr_is_journal()));
  spdlog::set_level(spdlog::level::from_str(level));
  spdlog::flush_on(spdlog::level::info);
}

void set_log_level(const std::string& level) { spdlog::set_level(spdlog::level::from_str(level)); }

}  // namespace unima::platform
