#include "config/source_ref_parser.hpp"

#include <cctype>

#include <fmt/format.h>

#include "banks/number_text.hpp"

namespace unima::config {

namespace {

using banks::BankId;

using banks::parse_number;

bool is_name(std::string_view s) {
  if (s.empty() || !(std::islower(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::islower(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) || c == '_'))
      return false;
  return true;
}

bool is_mapped_bits(const banks::SourceRef& ref) {
  return ref.bank == BankId::B || (ref.bank == BankId::C && (ref.offset == banks::c_bank::user_binary_inputs ||
                                                              ref.offset == banks::c_bank::user_binary_outputs));
}

// Which sources would make a mapped register read itself. A bit may come from A, so A
// may not show the mapped bits: A: [C+0x10] with user_inputs: [A+0x00.0] never ends a
// read (found with the config loader's fuzz target, docs/fuzzing.md).
std::optional<std::string> circular(const banks::SourceRef& ref, SourceUse use) {
  if (use == SourceUse::analog && ref.bank == BankId::A) return "bank A cannot be a source of bank A";
  if (use == SourceUse::analog && is_mapped_bits(ref))
    return "mapped bits (B, C+0x10, C+0x12) cannot be a source of bank A, whose bits they may show";
  if (use == SourceUse::bit && is_mapped_bits(ref))
    return "mapped bits (B, C+0x10, C+0x12) cannot be the source of mapped bits";
  return std::nullopt;
}

}  // namespace

std::variant<banks::SourceRef, std::string> parse_source_ref(std::string_view text, const banks::BankShapes& shapes,
                                                             SourceUse use) {
  const auto syntax = [&] {
    return fmt::format("'{}' is not a source (write e.g. D1+0x21, D1.oil_temperature{})", text,
                       use == SourceUse::bit ? ", D1+0x15.3, X.0" : "");
  };
  std::size_t bank_end = 0;
  while (bank_end < text.size() && std::isalnum(static_cast<unsigned char>(text[bank_end]))) ++bank_end;
  const auto bank = banks::parse_bank_name(text.substr(0, bank_end));
  if (!bank) return bank_end == 0 ? syntax() : fmt::format("'{}': unknown bank '{}'", text, text.substr(0, bank_end));
  const auto& shape = shapes[index_of(*bank)];
  if (shape.length == 0)
    return fmt::format("'{}': bank {} has no device configured (devices.{})", text, banks::bank_name(*bank),
                       banks::bank_name(*bank));

  banks::SourceRef ref;
  ref.bank = *bank;
  ref.text = std::string(text);
  std::string_view rest = text.substr(bank_end);
  std::string_view bit_text;
  if (rest.starts_with("+")) {
    const auto dot = rest.find('.');
    const auto number = parse_number(rest.substr(1, dot == std::string_view::npos ? std::string_view::npos : dot - 1));
    if (!number) return syntax();
    if (*number >= shape.length)
      return fmt::format("'{}': offset 0x{:02X} is past the end of bank {} ({} registers)", text, *number,
                         banks::bank_name(*bank), shape.length);
    if (*number >= banks::filled_length(shape))
      return fmt::format("'{}': offset 0x{:02X} is past the end of the {} table of bank {} ({} registers): it always "
                         "reads 0x7FFF",
                         text, *number, shape.table->id, banks::bank_name(*bank), banks::filled_length(shape));
    ref.offset = static_cast<std::uint16_t>(*number);
    if (dot != std::string_view::npos) bit_text = rest.substr(dot + 1);
  } else if (rest.starts_with(".")) {
    rest.remove_prefix(1);
    const auto dot = rest.find('.');
    const auto name = rest.substr(0, dot);
    if (dot != std::string_view::npos) bit_text = rest.substr(dot + 1);
    if (parse_number(name) && dot == std::string_view::npos) {
      bit_text = name;  // X.0: bit 0 of the bank's first register
    } else if (!is_name(name)) {
      return syntax();
    } else if (!shape.table) {
      return fmt::format("'{}': bank {} has no named registers; write {}+0x00", text, banks::bank_name(*bank),
                         banks::bank_name(*bank));
    } else if (const auto* reg = shape.table->find(name)) {
      ref.offset = reg->offset;
    } else if (const auto field = shape.table->find_bit(name); field && bit_text.empty()) {
      ref.offset = field->offset;
      ref.bit = field->bit;
    } else {
      return fmt::format("'{}': {} ({}) has no register or single-bit field named '{}'", text, banks::bank_name(*bank),
                         shape.table->id, name);
    }
  } else {
    return syntax();
  }

  if (!bit_text.empty()) {
    const auto bit = parse_number(bit_text);
    if (!bit || *bit > 15) return fmt::format("'{}': bit '{}' is not 0..15", text, bit_text);
    ref.bit = static_cast<std::uint8_t>(*bit);
  }
  if (use == SourceUse::bit && !ref.bit)
    return fmt::format("'{}' names a whole register; a bit source needs a bit, e.g. {}.0", text, text);
  if (use == SourceUse::analog && ref.bit)
    return fmt::format("'{}' is a bit; an analog register needs a whole register", text);
  if (const auto problem = circular(ref, use)) return fmt::format("'{}': {}", text, *problem);
  return ref;
}

}  // namespace unima::config
