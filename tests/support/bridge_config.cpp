#include "tests/support/bridge_config.hpp"

#include <sstream>

namespace unima::test_support {

std::string BridgeConfig::yaml() const {
  std::ostringstream out;
  out << "unimabus:\n"
      << "  address: 5\n"
      << "  transport: " << transport << "\n";
  if (transport == "feed")
    out << "  listen: " << (feed_listen.empty() ? "127.0.0.1:" + std::to_string(feed_port) : feed_listen) << "\n";
  out << unimabus_extra << "modbus:\n";
  if (!mode.empty()) out << "  mode: " << mode << "\n";
  out << "  address: 1\n";
  if (modbus_port != 0) out << "  tcp: { listen: 127.0.0.1, port: " << modbus_port << tcp_extra << " }\n";
  std::string master_body = master;
  if (line.starts_with("master-tcp: ")) {
    const auto target = line.substr(12);
    master_body = master_body.empty() ? "tcp: " + target : master_body + ", tcp: " + target;
  } else if (!line.empty()) {
    out << "  " << line << "\n";
  }
  if (!master_body.empty()) out << "  master: { " << master_body << " }\n";
  out << modbus_extra;
  if (!banks.empty()) out << "banks: " << banks << "\n";
  if (!devices.empty()) out << "devices: " << devices << "\n";
  if (!blocks.empty()) out << "blocks:\n" << blocks;
  if (!log_level.empty()) out << "log: { level: " << log_level << " }\n";
  if (!status_socket.empty()) out << "status: { socket: " << status_socket << " }\n";
  out << monitor_section << extra;
  return out.str();
}

}  // namespace unima::test_support
