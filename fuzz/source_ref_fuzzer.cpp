// Fuzz target: source references (SPEC §7: `D1+0x21`, `D1.oil_temperature`, `X.0`,
// `D1+0x15.3`), as mapping entries and blocks write them, parsed by
// config::parse_source_ref against the banks of a config.
//
// Input: byte 0 chooses the device types of D1..D4 (low 7 bits) and whether a bit (0x80)
// or a whole register is wanted; the rest is the reference.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <variant>
#include <vector>

#include "banks/register_store.hpp"
#include "banks/table_catalog.hpp"
#include "config/source_ref_parser.hpp"
#include "fuzz/fuzz_check.hpp"

namespace {

using namespace unima;

// The tables of D1..D4. Choice 0 is config/examples/four-devices.yaml's (the seeds name
// its registers); the others rotate through the nine device types and no device at all,
// so each type turns up in each bank.
banks::BankShapes shapes_for(std::uint8_t choice) {
  static const std::vector<std::string_view> types = banks::device_type_ids();
  std::array<const banks::DeviceTable*, 4> tables{};
  if (choice == 0) {
    tables = {banks::find_device_type("unigen-chp"), banks::find_device_type("uvr"), banks::find_device_type("usc"),
              banks::find_device_type("uis")};
  } else {
    for (std::size_t n = 0; n < tables.size(); ++n) {
      const std::size_t pick = (choice + 3u * n) % (types.size() + 1);
      if (pick < types.size()) tables[n] = banks::find_device_type(types[pick]);
    }
  }
  return banks::standard_shapes(tables, banks::io_module_table(), banks::bridge_internal_table());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const auto shapes = shapes_for(static_cast<std::uint8_t>(data[0] & 0x7F));
  const auto use = (data[0] & 0x80) ? config::SourceUse::bit : config::SourceUse::analog;
  const auto text = std::string_view(reinterpret_cast<const char*>(data) + 1, size - 1);

  const auto parsed = config::parse_source_ref(text, shapes, use);
  if (const auto* error = std::get_if<std::string>(&parsed)) {
    FUZZ_CHECK(!error->empty());
    return 0;
  }
  const auto& ref = std::get<banks::SourceRef>(parsed);
  const auto& shape = shapes[banks::index_of(ref.bank)];
  FUZZ_CHECK(shape.length > 0 && ref.offset < banks::filled_length(shape));  // never past a table
  FUZZ_CHECK(ref.text == text);
  FUZZ_CHECK((use == config::SourceUse::bit) == ref.bit.has_value());
  if (ref.bit) FUZZ_CHECK(*ref.bit <= 15);
  // Never a source that would read itself (bank A from A, mapped bits from mapped bits).
  if (use == config::SourceUse::analog) FUZZ_CHECK(ref.bank != banks::BankId::A);
  if (use == config::SourceUse::bit) FUZZ_CHECK(ref.bank != banks::BankId::B);

  // The store reads it, as banks A, B and the blocks do at every Modbus read.
  banks::RegisterStore store(shapes);
  const auto value = store.read_source(ref);
  if (ref.bit) FUZZ_CHECK(value <= 1);
  return 0;
}
