#include "io/tls_context.hpp"

namespace unima::io {

std::shared_ptr<asio::ssl::context> make_server_tls_context(const tls::TlsFiles& files, std::string_view section) {
  // Asio's context takes the handle over and frees it.
  return std::make_shared<asio::ssl::context>(tls::load_server_credentials(files, section).release());
}

}  // namespace unima::io
