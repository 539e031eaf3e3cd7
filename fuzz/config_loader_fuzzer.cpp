// Fuzz target: the config loader (SPEC §7) on any text, as `unima-bridge check`, the
// daemon's start and a reload read a file: config::load_text. A config it refuses is a
// ConfigError naming file:line:column; any other exception escapes and is a finding. A
// config it accepts must start: the banks are built and every served register read (as
// io::build_banks and a Modbus read do), its warnings, its register map and, in
// master mode, the master's plan are made.
//
// The replay transport reads the recording its config names. Inputs that could name a
// file that never ends or blocks (/dev/zero, /proc/self/fd/0) are skipped: a fuzzer would
// find those, and they are not what this target is about. The seeds replay /dev/null, an
// empty recording.

#include <cstddef>
#include <cstdio>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "config/config.hpp"
#include "config/master_setup.hpp"
#include "config/register_map.hpp"
#include "fuzz/bridge_banks.hpp"
#include "fuzz/fuzz_check.hpp"

namespace {

using namespace unima;

constexpr std::string_view origin = "fuzz.yaml";

// A literal path to a device or a kernel file; a backslash could spell one in a
// double-quoted YAML string ("\x2Fdev", or an escaped line break inside "/de\
// v/zero"), so every input holding one is skipped too.
bool may_name_a_special_file(std::string_view text) {
  if (text.find('\\') != std::string_view::npos) return true;
  for (const std::string_view part : {"proc/", "sys/"})
    if (text.find(part) != std::string_view::npos) return true;
  for (auto at = text.find("dev/"); at != std::string_view::npos; at = text.find("dev/", at + 1))
    if (text.substr(at + 4, 4) != "null") return true;
  return false;
}

// "fuzz.yaml:12:7: …", line and column from 1 (SPEC §7).
bool names_its_position(std::string_view message) {
  if (!message.starts_with(origin)) return false;
  std::size_t at = origin.size();
  for (int field = 0; field < 2; ++field) {
    if (at >= message.size() || message[at] != ':') return false;
    const auto digits_from = ++at;
    while (at < message.size() && message[at] >= '0' && message[at] <= '9') ++at;
    if (at == digits_from || message[digits_from] == '0') return false;  // empty, or line/column 0
  }
  return message.substr(at).starts_with(": ");
}

// What the daemon does with a config it was given, short of opening sockets.
void start(const config::Config& config) {
  const auto map = config::address_map(config);  // validated by the loader: never throws
  fuzz::BridgeBanks banks(config, map);
  for (int pass = 0; pass < 2; ++pass) {
    for (const auto& window : map.windows()) {
      std::vector<std::uint16_t> values(window.count);
      const bool readable = banks.space.read(window.first, values);
      if (window.kind != banks::Window::Kind::write_block && !banks::is_write_bank(window.bank)) FUZZ_CHECK(readable);
    }
    banks.bring_plant_online();
  }
  (void)config::warnings(config);
  (void)config::register_map(config);
  if (config.modbus.mode == config::ModbusMode::master) (void)config::master_plan(config::master_setup(config));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (may_name_a_special_file(text)) return -1;  // not kept in the corpus either
  try {
    start(config::load_text(text, std::string(origin)));
  } catch (const config::ConfigError& e) {
    if (!names_its_position(e.what())) {
      std::fprintf(stderr, "config error without its position: %s\n", e.what());
      FUZZ_CHECK(false && "every config error names file:line:column");
    }
  }
  return 0;
}
