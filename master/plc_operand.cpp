#include "master/plc_operand.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>

#include <fmt/format.h>

namespace unima::master {

std::variant<ResolvedOperand, std::string> resolve_operand(const DeviceProfile& profile, std::string_view text) {
  std::string letters;
  std::size_t at = 0;
  while (at < text.size() && std::isalpha(static_cast<unsigned char>(text[at])))
    letters += static_cast<char>(std::toupper(static_cast<unsigned char>(text[at++])));
  const auto digits = text.substr(at);
  std::string known;
  for (const auto& c : profile.operands) known += (known.empty() ? "" : ", ") + c.name;
  const auto* c = profile.find_operand_class(letters);
  if (letters.empty() || digits.empty())
    return fmt::format("'{}' is not an operand of {} (write a class and a number, e.g. D200; classes: {})", text,
                       profile.id, known);
  if (!c) return fmt::format("{} has no operand class '{}' (classes: {})", profile.id, letters, known);
  unsigned number = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), number, static_cast<int>(c->base));
  if (ec != std::errc{} || end != digits.data() + digits.size()) {
    if (c->base == 8 && std::all_of(digits.begin(), digits.end(), [](char d) { return d >= '0' && d <= '9'; }))
      return fmt::format("'{}': {} operands are numbered in octal ({}0..{}7, {}10..), so '{}' has no 8 or 9",
                         text, c->name, c->name, c->name, c->name, digits);
    return fmt::format("'{}': '{}' is not a number", text, digits);
  }
  if (number < c->first || number > c->last)
    return fmt::format("'{}' is outside {}'s {}..{}", text, c->name, c->format(c->first), c->format(c->last));
  return ResolvedOperand{c, number, static_cast<std::uint16_t>(c->offset + (number - c->first))};
}

}  // namespace unima::master
