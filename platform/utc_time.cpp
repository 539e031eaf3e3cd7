#include "platform/utc_time.hpp"

#include <charconv>
#include <cstdint>
#include <cstring>

namespace unima::platform {

namespace {

using Clock = std::chrono::system_clock;

struct SecondText {
  std::int64_t second = -1;
  char text[19];  // "YYYY-MM-DDTHH:MM:SS"
};
thread_local SecondText last_second;

char* digits(char* out, unsigned value, int width) {
  for (int i = width - 1; i >= 0; --i) {
    out[i] = static_cast<char>('0' + value % 10);
    value /= 10;
  }
  return out + width;
}

std::optional<unsigned> number(std::string_view text) {
  unsigned value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc{} || end != text.data() + text.size()) return std::nullopt;
  return value;
}

}  // namespace

char* write_utc_time(char* out, Clock::time_point time) {
  using namespace std::chrono;
  const auto micros = floor<microseconds>(time);
  const auto second = floor<seconds>(micros);
  if (last_second.second != second.time_since_epoch().count()) {
    const auto day = floor<days>(second);
    const year_month_day date{day};
    const hh_mm_ss clock{second - day};
    char* p = last_second.text;
    p = digits(p, static_cast<unsigned>(static_cast<int>(date.year())), 4);
    *p++ = '-';
    p = digits(p, static_cast<unsigned>(date.month()), 2);
    *p++ = '-';
    p = digits(p, static_cast<unsigned>(date.day()), 2);
    *p++ = 'T';
    p = digits(p, static_cast<unsigned>(clock.hours().count()), 2);
    *p++ = ':';
    p = digits(p, static_cast<unsigned>(clock.minutes().count()), 2);
    *p++ = ':';
    digits(p, static_cast<unsigned>(clock.seconds().count()), 2);
    last_second.second = second.time_since_epoch().count();
  }
  std::memcpy(out, last_second.text, sizeof last_second.text);
  char* p = out + sizeof last_second.text;
  *p++ = '.';
  p = digits(p, static_cast<unsigned>((micros - second).count()), 6);
  *p++ = 'Z';
  return p;
}

void append_utc_time(std::string& out, Clock::time_point time) {
  const auto start = out.size();
  out.resize(start + utc_time_size);
  write_utc_time(out.data() + start, time);
}

std::string utc_time_text(Clock::time_point time) {
  std::string text;
  append_utc_time(text, time);
  return text;
}

std::optional<Clock::time_point> parse_utc_time(std::string_view text) {
  using namespace std::chrono;
  if (text.size() != utc_time_size || text[4] != '-' || text[7] != '-' || text[10] != 'T' || text[13] != ':' ||
      text[16] != ':' || text[19] != '.' || text[26] != 'Z')
    return std::nullopt;
  const auto field = [&](std::size_t at, std::size_t width) { return number(text.substr(at, width)); };
  const auto y = field(0, 4), mo = field(5, 2), d = field(8, 2), h = field(11, 2), mi = field(14, 2), s = field(17, 2),
             us = field(20, 6);
  if (!y || !mo || !d || !h || !mi || !s || !us || *h > 23 || *mi > 59 || *s > 60) return std::nullopt;
  const year_month_day date{year(static_cast<int>(*y)), month(*mo), day(*d)};
  if (!date.ok()) return std::nullopt;
  return time_point_cast<Clock::duration>(sys_days(date) + hours(*h) + minutes(*mi) + seconds(*s) + microseconds(*us));
}

}  // namespace unima::platform
