// Fuzz target: a recording to replay (SPEC §6 `replay`), as the config loader reads the
// file: unimabus::parse_recording, then unimabus::ReplaySchedule playing it as
// io/unimabus/replay_transport does, for a while.
//
// Input: byte 0 chooses the speed and whether the recording loops; the rest is the file.

#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz/fuzz_check.hpp"
#include "unimabus/feed_codec.hpp"
#include "unimabus/recording.hpp"

namespace {

using namespace unima;

constexpr std::string_view origin = "fuzz.jsonl";

void play(const unimabus::Recording& recording, double speed, bool loop) {
  unimabus::ReplaySchedule schedule(recording, speed, loop);
  unimabus::ReplaySchedule::Duration last_due{0};
  std::size_t taken = 0;
  // At most two passes of the recording: enough to see a loop start again.
  while (taken < 2 * recording.entries.size() + 2) {
    const auto due = schedule.next_due();
    if (!due) break;
    FUZZ_CHECK(*due >= last_due);  // the times never go back, not even into the next pass
    last_due = *due;
    // The transport waits until it is due and takes it.
    const auto* entry = schedule.take_due(*due);
    FUZZ_CHECK(entry != nullptr);
    FUZZ_CHECK(entry >= recording.entries.data() && entry < recording.entries.data() + recording.entries.size());
    ++taken;
  }
  if (!loop) FUZZ_CHECK(taken == recording.entries.size());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static constexpr double speeds[] = {1.0, 0.001, 1000.0, 2.5};
  const double speed = speeds[data[0] % std::size(speeds)];
  const bool loop = (data[0] & 0x04) != 0;
  const auto text = std::string_view(reinterpret_cast<const char*>(data) + 1, size - 1);

  unimabus::Recording recording;
  try {
    recording = unimabus::parse_recording(text, origin);
  } catch (const unimabus::RecordingError& e) {
    // "fuzz.jsonl:3: why" (SPEC §6: a bad line is an error naming file:line).
    const std::string_view message = e.what();
    FUZZ_CHECK(message.starts_with(std::string(origin) + ":") && message.size() > origin.size() + 1);
    FUZZ_CHECK(message[origin.size() + 1] >= '1' && message[origin.size() + 1] <= '9');
    return 0;
  }
  FUZZ_CHECK(recording.origin == origin);
  std::size_t last_line = 0;
  double last_t = 0;
  for (const auto& entry : recording.entries) {
    FUZZ_CHECK(entry.line > last_line && entry.t >= last_t && std::isfinite(entry.t) && entry.t <= 1e9);
    FUZZ_CHECK(!entry.telegram.values.empty());
    last_line = entry.line;
    last_t = entry.t;
  }
  play(recording, speed, loop);
  return 0;
}
