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

struct Config {
  std::string file;
  UnimabusConfig unimabus;
  ModbusConfig modbus;
  std::array<std::uint16_t, banks::bank_count> bank_bases{};
  std::array<std::string, banks::bank_count> bank_origins;  // "file:line:col" of banks set in the file
  std::array<std::optional<DeviceConfig>, 4> devices;
  LogConfig log;
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
