#include "io/control_socket.hpp"

#include <fcntl.h>
#include <sys/stat.h>

#include <filesystem>
#include <memory>
#include <stdexcept>

#include <spdlog/spdlog.h>

#include "config/socket_path.hpp"

namespace unima::io {

using asio::local::stream_protocol;

namespace {

bool someone_answers(asio::io_context& io, const std::string& path) {
  stream_protocol::socket probe(io);
  boost::system::error_code ec;
  probe.connect(stream_protocol::endpoint(path), ec);
  return !ec;
}

}  // namespace

ControlSocket::ControlSocket(asio::io_context& io, std::string path, DocumentFn document)
    : path_(std::move(path)), document_(std::move(document)), acceptor_(io),
      accepting_(acceptor_, "status", [this](stream_protocol::socket socket) { answer(std::move(socket)); }) {
  const auto directory = std::filesystem::path(path_).parent_path();
  std::error_code ignored;  // the bind says what went wrong
  if (!directory.empty()) std::filesystem::create_directories(directory, ignored);
  if (someone_answers(io, path_))
    throw std::runtime_error("status: " + path_ + " is answered by another process (is another daemon running?)");
  config::clear_socket_path(path_, "status.socket");  // a socket file a previous run left behind
  boost::system::error_code ec;
  acceptor_.open(stream_protocol(), ec);
  if (!ec) acceptor_.bind(stream_protocol::endpoint(path_), ec);
  // Asking needs write permission on the socket: the daemon's user and group may ask (as
  // for the monitor log, 0640), whatever the umask. Never through a symbolic link that
  // took the socket's place since the bind (SPEC §10). Before the listen, so that nobody
  // is answered while the socket still has the umask's mode.
  if (!ec) ::fchmodat(AT_FDCWD, path_.c_str(), 0660, AT_SYMLINK_NOFOLLOW);
  if (!ec) acceptor_.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) throw std::runtime_error("status: cannot listen on " + path_ + ": " + ec.message());
}

ControlSocket::~ControlSocket() { stop(); }

void ControlSocket::start() {
  spdlog::info("status: answering on {}", path_);
  accepting_.start();
}

void ControlSocket::stop() {
  if (stopped_) return;
  stopped_ = true;
  boost::system::error_code ec;
  accepting_.stop();
  acceptor_.close(ec);
  config::remove_socket_file(path_);
}

// A few kB: the kernel takes it at once, so a client that never reads holds nothing.
void ControlSocket::answer(stream_protocol::socket socket) {
  auto connection = std::make_shared<stream_protocol::socket>(std::move(socket));
  auto text = std::make_shared<std::string>(document_() + "\n");
  asio::async_write(*connection, asio::buffer(*text), [connection, text](const boost::system::error_code&, std::size_t) {
    boost::system::error_code ignored;
    connection->shutdown(stream_protocol::socket::shutdown_both, ignored);
  });
}

}  // namespace unima::io
