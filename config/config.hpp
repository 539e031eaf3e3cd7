#pragma once
// The daemon's configuration (SPEC §7), as loaded from YAML and validated.

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "banks/address_map.hpp"
#include "banks/bank_id.hpp"
#include "banks/device_table.hpp"
#include "banks/register_store.hpp"

namespace unima::config {

using Duration = std::chrono::milliseconds;

enum class TransportKind { sim, feed, replay };
enum class ModbusMode { slave, master };

struct SimConfig {
  std::uint32_t seed = 1;
  Duration period = std::chrono::seconds(1);
  std::vector<unsigned> io_modules;  // slots 1..7 the simulator fills besides the D_N devices
};

struct UnimabusConfig {
  std::uint8_t address = 1;  // the bridge's own UnimaBUS address, seed "Addr"
  TransportKind transport = TransportKind::sim;
  std::string listen;        // feed: "host:port" or "unix:/path"
  Duration offline_after = std::chrono::seconds(5);
  SimConfig sim;
};

struct TcpSlaveConfig {
  std::string listen = "0.0.0.0";
  std::uint16_t port = 502;
  unsigned max_clients = 128;
  Duration idle_timeout = std::chrono::seconds(60);  // 0: never
};

/// Functions beyond the seed's 4 and 6 (SPEC §3), each on by default.
struct Extensions {
  bool function_3 = true;
  bool function_16 = true;
  bool function_43 = true;
};

struct ModbusConfig {
  ModbusMode mode = ModbusMode::slave;
  std::uint8_t address = 1;  // seed "MBSAddr"
  std::optional<TcpSlaveConfig> tcp;
  bool readable_write_banks = true;
  Extensions extensions;
};

struct DeviceConfig {
  const banks::DeviceTable* table = nullptr;  // seed "Dev_NSel"
  std::uint8_t address = 0;                   // seed "DevNAddr"
};

struct LogConfig {
  std::string level = "info";
};

/// The monitor's command filter (SPEC §5); nullopt is "xx", any.
struct MonitorFilterConfig {
  std::optional<std::uint8_t> address;
  std::optional<std::uint8_t> function;
  std::uint16_t from = 0x0000;
  std::uint16_t to = 0xFFFF;
};

/// A capture indicator: the last value seen for this address + register (SPEC §5).
struct IndicatorConfig {
  std::uint8_t address = 0;
  std::uint16_t reg = 0;
};

enum class MonitorFormat { text, json };

/// The monitor log (SPEC §5, seed §8): off unless a file or stdout is set.
struct MonitorConfig {
  std::string file;             // size-rotated: file, file.1 .. file.<max_files>
  bool to_stdout = false;       // key "stdout"
  MonitorFormat format = MonitorFormat::text;
  std::uint64_t max_size = 10ull << 20;
  unsigned max_files = 5;
  unsigned queue = 4096;        // transactions waiting for the writer; more are dropped and counted
  MonitorFilterConfig filter;
  std::vector<IndicatorConfig> indicators;  // at most 4
  bool enabled() const { return !file.empty() || to_stdout; }
};

/// `unima-bridge status` asks the daemon on this unix socket.
struct StatusConfig {
  std::string socket = "/run/unima-bridge/control.sock";
};

struct Config {
  std::string file;
  UnimabusConfig unimabus;
  ModbusConfig modbus;
  std::array<std::uint16_t, banks::bank_count> bank_bases{};
  std::array<std::string, banks::bank_count> bank_origins;  // "file:line:col" of banks set in the file
  std::array<std::optional<DeviceConfig>, 4> devices;
  LogConfig log;
  MonitorConfig monitor;
  StatusConfig status;
};

/// A config problem; what() starts with "file:line:column: " (1-based).
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

Config load_file(const std::string& path);
/// `origin` names the text in errors, as the file name would.
Config load_text(const std::string& text, const std::string& origin);

/// Bank sizes and tables of this config.
banks::BankShapes bank_shapes(const Config& config);
/// Every served window (banks now; block registers with issue #3). Validated by the loader.
banks::AddressMap address_map(const Config& config);

}  // namespace unima::config
