#pragma once
// Why a server of the daemon cannot listen, said with the config key that chose the
// address: "bridge.yaml:3:30: modbus.tcp.port 5020: address 127.0.0.1:5020 is in use by
// another program". One wording for the Modbus TCP and TLS ports, HTTP and the feed.

#include <string>
#include <string_view>

#include "platform/asio.hpp"

namespace unima::io {

/// `origin` is the key's "file:line:col"; `setting` the key and its value as written
/// ("modbus.tcp.port 5020", "unimabus.listen 127.0.0.1:5000"); `address` what was bound.
/// "127.0.0.1:502", "[::]:502".
std::string listen_address(std::string_view host, unsigned port);

std::string listen_error(std::string_view origin, std::string_view setting, std::string_view address,
                         const boost::system::error_code& error);

}  // namespace unima::io
