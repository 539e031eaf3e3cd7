#include "banks/address_map.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace unima::banks {

namespace {
std::string describe(const Window& w) {
  return fmt::format("{} (0x{:04X}..0x{:04X})", w.name, w.first, w.end() - 1);
}
std::string located(const Window& a, const Window* b, const std::string& message) {
  const std::string& origin = b && !b->origin.empty() ? b->origin : a.origin;
  return origin.empty() ? message : origin + ": " + message;
}
}  // namespace

AddressMap::AddressMap(std::vector<Window> windows) : windows_(std::move(windows)) {
  std::erase_if(windows_, [](const Window& w) { return w.count == 0; });
  // Stable, so that an overlap message names the windows in the order the config gave them.
  std::stable_sort(windows_.begin(), windows_.end(), [](const Window& a, const Window& b) { return a.first < b.first; });
  for (std::size_t i = 0; i < windows_.size(); ++i) {
    const auto& w = windows_[i];
    if (w.end() > 0x10000)
      throw OverlapError(located(w, nullptr, fmt::format("{} (0x{:04X}, {} registers) runs past the last register address 0xFFFF",
                                                         w.name, w.first, w.count)));
    if (i > 0 && windows_[i - 1].end() > w.first)
      throw OverlapError(
          located(windows_[i - 1], &w, fmt::format("{} overlaps {}", describe(windows_[i - 1]), describe(w))));
  }
}

const Window* AddressMap::find(std::uint16_t address) const {
  auto it = std::upper_bound(windows_.begin(), windows_.end(), address,
                             [](std::uint16_t a, const Window& w) { return a < w.first; });
  if (it == windows_.begin()) return nullptr;
  --it;
  return address < it->end() ? &*it : nullptr;
}

const Window* AddressMap::adjacent_after(const Window& window) const {
  const auto index = static_cast<std::size_t>(&window - windows_.data());
  if (index + 1 >= windows_.size()) return nullptr;
  const auto& next = windows_[index + 1];
  return next.first == window.end() ? &next : nullptr;
}

}  // namespace unima::banks
