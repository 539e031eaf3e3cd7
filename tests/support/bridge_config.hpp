#pragma once
// The daemon's config as the integration tests write it: a feed transport and a Modbus
// TCP slave on loopback, the rest as a test sets it — slave mode with its banks and
// devices (the default), or master mode with its line and blocks. One builder for both.

#include <cstdint>
#include <string>

namespace unima::test_support {

struct BridgeConfig {
  std::uint16_t modbus_port = 0;  // the plain Modbus TCP slave's; 0: none (modbus.tcp absent)
  std::uint16_t feed_port = 0;
  std::string feed_listen;  // overrides 127.0.0.1:feed_port when set
  std::string transport = "feed";  // sim or replay take their keys from unimabus_extra
  std::string mode;         // "master", or empty for the default (slave)
  std::string banks = "{ D1: 0x0011, W: 0x0100 }";   // empty: the default layout
  std::string devices = "{ D1: { type: unigen-chp, address: 5 } }";
  std::string tcp_extra;       // more keys of modbus.tcp, each starting with ", "
  std::string unimabus_extra;  // more lines inside unimabus:
  std::string modbus_extra;    // more lines inside modbus:
  std::string line;            // "rtu: { device: ..., baud: 38400 }", or "master-tcp: host:port"
  std::string master;          // the body of modbus.master, without tcp
  std::string blocks;          // YAML list items, each "  - { ... }\n"
  std::string log_level;       // log: { level: ... } when set
  std::string status_socket;   // status: { socket: ... } when set
  std::string monitor_section;  // "monitor:\n  file: ...\n" when set
  std::string extra;           // more top-level sections

  std::string yaml() const;
};

}  // namespace unima::test_support
