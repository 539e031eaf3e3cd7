#pragma once
// Boost.Beast's HTTP (and HTTPS over Asio's SSL stream), behind the project's Asio header (platform/asio.hpp must come first:
// Debian 12's Boost 1.74 with GCC 12 in C++20). Only the HTTP server includes this.

#include "platform/asio_ssl.hpp"

#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>

namespace unima {
namespace beast = boost::beast;
}  // namespace unima
