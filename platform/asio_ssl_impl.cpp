// Asio SSL's compiled part, once for the whole program (see asio_impl.cpp). An object of
// its own, so that a program which never uses TLS does not pull it in from the archive.

#include "platform/asio_ssl.hpp"

#ifdef BOOST_ASIO_SEPARATE_COMPILATION
#include <boost/asio/ssl/impl/src.hpp>
#endif
