#include "unimabus/recording.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace unima::unimabus {

namespace {

bool same_telegram(const Telegram& a, const Telegram& b) {
  return a.address == b.address && a.slot == b.slot && a.offset == b.offset && a.values == b.values &&
         a.device == b.device;
}

}  // namespace

bool operator==(const Recording& a, const Recording& b) {
  return a.entries.size() == b.entries.size() &&
         std::equal(a.entries.begin(), a.entries.end(), b.entries.begin(), [](const auto& x, const auto& y) {
           return x.t == y.t && same_telegram(x.telegram, y.telegram);
         });
}

Recording parse_recording(std::string_view text, std::string_view origin) {
  Recording recording;
  recording.origin = std::string(origin);
  std::size_t line_number = 0;
  while (!text.empty()) {
    ++line_number;
    const auto end = text.find('\n');
    auto line = text.substr(0, end);
    text = end == std::string_view::npos ? std::string_view{} : text.substr(end + 1);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.find_first_not_of(" \t") == std::string_view::npos) continue;
    auto parsed = parse_recorded_line(line);
    if (const auto* error = std::get_if<std::string>(&parsed))
      throw RecordingError(fmt::format("{}:{}: {}", origin, line_number, *error));
    auto& recorded = std::get<RecordedTelegram>(parsed);
    if (!recording.entries.empty() && recorded.t < recording.entries.back().t)
      throw RecordingError(fmt::format("{}:{}: \"t\" goes back from {} to {}; a recording's times never decrease",
                                       origin, line_number, recording.entries.back().t, recorded.t));
    recording.entries.push_back({recorded.t, line_number, std::move(recorded.telegram)});
  }
  return recording;
}

ReplaySchedule::ReplaySchedule(const Recording& recording, double speed, bool loop)
    : recording_(recording), speed_(speed), loop_(loop) {}

ReplaySchedule::Duration ReplaySchedule::due(std::size_t index, std::size_t pass) const {
  // The next pass begins one average interval after the last line, as the line after it
  // would have come; never sooner than shortest_pass after the pass began.
  const auto count = recording_.entries.size();
  const double interval = count > 1 ? recording_.duration() / static_cast<double>(count - 1) : 0.0;
  const double pass_seconds =
      std::max(recording_.duration() + interval, std::chrono::duration<double>(shortest_pass).count());
  const double seconds = (static_cast<double>(pass) * pass_seconds + recording_.entries[index].t) / speed_;
  // Converting a number of seconds that Duration cannot hold is undefined (found by fuzzing).
  if (!(seconds < std::chrono::duration<double>(latest_due).count())) return latest_due;
  return std::chrono::duration_cast<Duration>(std::chrono::duration<double>(seconds));
}

std::optional<ReplaySchedule::Duration> ReplaySchedule::next_due() const {
  if (index_ >= recording_.entries.size()) return std::nullopt;
  return due(index_, pass_);
}

const Recording::Entry* ReplaySchedule::take_due(Duration elapsed) {
  const auto next = next_due();
  if (!next || *next > elapsed) return nullptr;
  const auto* entry = &recording_.entries[index_];
  if (++index_ == recording_.entries.size() && loop_) {
    index_ = 0;
    ++pass_;
  }
  return entry;
}

}  // namespace unima::unimabus
