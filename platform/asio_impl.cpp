// Asio's compiled part, once for the whole program: the project builds Asio with
// BOOST_ASIO_SEPARATE_COMPILATION (platform/CMakeLists.txt), so its non-template functions
// are compiled here instead of inline in every translation unit that includes Asio. A Release
// build keeps Asio inline (platform/CMakeLists.txt) and this file empty.

#include "platform/asio.hpp"

#ifdef BOOST_ASIO_SEPARATE_COMPILATION
#include <boost/asio/impl/src.hpp>
#endif
