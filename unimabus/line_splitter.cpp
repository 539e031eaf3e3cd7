#include "unimabus/line_splitter.hpp"

namespace unima::unimabus {

void LineSplitter::feed(std::string_view bytes, const std::function<void(std::string_view)>& on_line,
                        const std::function<void()>& on_overlong) {
  while (!bytes.empty()) {
    const auto newline = bytes.find('\n');
    const auto piece = bytes.substr(0, newline);
    if (!discarding_) {
      // One more byte may be the "\r" of a "\r\n", which is not part of the line.
      if (partial_.size() + piece.size() > max_line_ + 1) {
        discarding_ = true;
        partial_.clear();
        on_overlong();
      } else {
        partial_.append(piece);
      }
    }
    if (newline == std::string_view::npos) return;
    bytes.remove_prefix(newline + 1);
    if (!discarding_) {
      std::string_view line = partial_;
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      if (line.size() > max_line_) on_overlong();
      else on_line(line);
    }
    partial_.clear();
    discarding_ = false;
  }
}

}  // namespace unima::unimabus
