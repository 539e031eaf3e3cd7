#pragma once
// Boost.Asio's SSL stream over OpenSSL (Modbus/TCP Security, SPEC §11), behind the
// project's Asio header (platform/asio.hpp, which must come first). Only what serves TLS
// includes this: it needs libssl at link time.

#include "platform/asio.hpp"

#include <boost/asio/ssl.hpp>
