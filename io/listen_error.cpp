#include "io/listen_error.hpp"

#include <cerrno>

#include <fmt/format.h>

namespace unima::io {

std::string listen_address(std::string_view host, unsigned port) {
  if (host.find(':') != std::string_view::npos) return fmt::format("[{}]:{}", host, port);
  return fmt::format("{}:{}", host, port);
}

std::string listen_error(std::string_view origin, std::string_view setting, std::string_view address,
                         const boost::system::error_code& error) {
  std::string why;
  if (error == boost::asio::error::address_in_use)
    why = fmt::format("address {} is in use by another program: stop that program, or choose another port", address);
  else if (error == boost::asio::error::access_denied)
    why = fmt::format("address {} is refused to this process: a port below 1024 needs CAP_NET_BIND_SERVICE, which "
                      "the systemd service gives; or choose a port above 1023",
                      address);
  else if (error.value() == EADDRNOTAVAIL)
    why = fmt::format("address {} is not an address of this machine", address);
  else
    why = fmt::format("cannot listen on {}: {}", address, error.message());
  return fmt::format("{}: {}: {}", origin, setting, why);
}

}  // namespace unima::io
