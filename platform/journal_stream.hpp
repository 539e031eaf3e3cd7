#pragma once
// Logging into systemd's journal through stderr: how to tell that stderr is the journal
// (systemd.exec(5), JOURNAL_STREAM) and the priority prefixes journald reads (sd-daemon(3)).

#include <sys/types.h>

#include <string_view>

#include <spdlog/common.h>

namespace unima::platform {

/// True when `journal_stream` ("device:inode" in decimal, as systemd sets JOURNAL_STREAM)
/// names the stream with this device and inode. A program started from a service inherits
/// the variable with a different stderr, so the variable alone proves nothing.
bool is_journal_stream(std::string_view journal_stream, dev_t device, ino_t inode);

/// The sd-daemon(3) prefix for a message of `level`: "<3>" error, "<4>" warning, "<6>"
/// info, "<7>" debug and trace, "<2>" critical; "" for off. journald takes the message's
/// priority from it and drops it from the text.
std::string_view journal_priority_prefix(spdlog::level::level_enum level);

}  // namespace unima::platform
