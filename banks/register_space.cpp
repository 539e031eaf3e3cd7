#include "banks/register_space.hpp"

#include <algorithm>

namespace unima::banks {

bool RegisterSpace::readable(const Window& w) const {
  if (w.kind == Window::Kind::read_block) return true;
  if (w.kind != Window::Kind::bank) return false;  // MBS_RegW registers are write-only (seed §7.1)
  return !is_write_bank(w.bank) || rules_.readable_write_banks;
}

template <typename Fn>
bool RegisterSpace::for_each_window(std::uint16_t first, std::size_t count, Fn&& fn) const {
  if (count == 0 || first + count > 0x10000) return false;
  const Window* w = map_.find(first);
  std::uint32_t address = first;
  std::size_t done = 0;
  while (w) {
    const std::size_t n = std::min<std::size_t>(count - done, w->end() - address);
    if (!fn(*w, static_cast<std::uint16_t>(address), done, n)) return false;
    done += n;
    address += n;
    if (done == count) return true;
    w = map_.adjacent_after(*w);
  }
  return false;
}

void RegisterSpace::read_window(const Window& w, std::uint16_t address, std::span<std::uint16_t> out) const {
  if (w.kind == Window::Kind::read_block) out[0] = store_.read_source(w.source);  // one register
  else store_.read(w.bank, static_cast<std::uint16_t>(address - w.first), out);
}

bool RegisterSpace::read(std::uint16_t first, std::span<std::uint16_t> out) const {
  // The usual read lies in one window: one lookup, one check, one copy. The general walk
  // below looks the first window up twice.
  if (const Window* w = map_.find(first); w && !out.empty() && first + out.size() <= w->end()) {
    if (!readable(*w)) return false;
    read_window(*w, first, out);
    return true;
  }
  // Check the whole range before reading any of it, as the bank reads are cheap but a
  // partial answer must never leave here.
  const bool all_readable =
      for_each_window(first, out.size(), [&](const Window& w, std::uint16_t, std::size_t, std::size_t) {
        return readable(w);
      });
  if (!all_readable) return false;
  for_each_window(first, out.size(), [&](const Window& w, std::uint16_t address, std::size_t done, std::size_t n) {
    read_window(w, address, out.subspan(done, n));
    return true;
  });
  return true;
}

bool RegisterSpace::resolve(std::uint16_t first, std::span<const std::uint16_t> values, const Landed& landed) const {
  const bool all_writable = for_each_window(
      first, values.size(), [&](const Window& w, std::uint16_t, std::size_t, std::size_t) { return writable(w); });
  if (!all_writable) return false;
  for_each_window(first, values.size(), [&](const Window& w, std::uint16_t address, std::size_t done, std::size_t n) {
    if (w.kind == Window::Kind::write_block) {
      landed({BankId::C, static_cast<std::uint16_t>(c_bank::user_analog_outputs + w.output - 1), values[done]});
      return true;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const auto offset = static_cast<std::uint16_t>(address - w.first + i);
      landed({w.bank, offset, values[done + i]});
    }
    return true;
  });
  return true;
}

}  // namespace unima::banks
