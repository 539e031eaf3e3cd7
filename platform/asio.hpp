#pragma once
// The project's one way to include Boost.Asio. Debian 12's Boost 1.74 Asio, compiled as
// C++20 by GCC 12, uses std::exchange in awaitable.hpp without including <utility>; the
// include below must come first.

#include <utility>

#include <boost/asio.hpp>

namespace unima {
namespace asio = boost::asio;
}  // namespace unima
