#include "io/control_socket.hpp"

#include <fcntl.h>
#include <sys/socket.h>
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

ControlSocket::ControlSocket(asio::io_context& io, std::string path, DocumentFn document, RequestFn request)
    : path_(std::move(path)), document_(std::move(document)), request_(std::move(request)), acceptor_(io),
      accepting_(acceptor_, "status", [this](stream_protocol::socket socket) { accepted(std::move(socket)); }) {
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

// Its handlers hold the connection and copies of the two answers, never the ControlSocket:
// a reload that moves the socket's path destroys the old one with connections still open.
struct ControlSocket::Connection {
  Connection(stream_protocol::socket s, DocumentFn d, RequestFn r)
      : socket(std::move(s)), document(std::move(d)), request_fn(std::move(r)), timer(socket.get_executor()) {}
  stream_protocol::socket socket;
  DocumentFn document;
  RequestFn request_fn;
  asio::steady_timer timer;
  std::string request;
  bool decided = false;  // the grace ended one way or the other
};

void ControlSocket::accepted(stream_protocol::socket socket) {
  auto connection = std::make_shared<Connection>(std::move(socket), document_, request_);
  if (!request_) return answer_status(connection);
  // Whichever comes first — a byte (or the client's end) or the grace's end — decides.
  connection->timer.expires_after(request_grace);
  connection->timer.async_wait([connection](const boost::system::error_code& ec) {
    if (ec || connection->decided) return;
    connection->decided = true;
    boost::system::error_code ignored;
    connection->socket.cancel(ignored);
    answer_status(connection);
  });
  connection->socket.async_wait(stream_protocol::socket::wait_read, [connection](const boost::system::error_code& ec) {
    if (ec || connection->decided) return;
    connection->decided = true;
    connection->timer.cancel();
    if (connection->socket.available() == 0) return answer_status(connection);  // the client's end: it reads
    read_request(connection);
  });
}

// A few kB: the kernel takes it at once, so a client that never reads holds nothing.
void ControlSocket::answer_status(const std::shared_ptr<Connection>& connection) {
  auto text = std::make_shared<std::string>(connection->document() + "\n");
  asio::async_write(connection->socket, asio::buffer(*text), [connection, text](const boost::system::error_code&, std::size_t) {
    boost::system::error_code ignored;
    connection->socket.shutdown(stream_protocol::socket::shutdown_both, ignored);
  });
}

// One line, within max_request_bytes and a few seconds: a client that dribbles or sends
// without end holds one socket for that long at most.
void ControlSocket::read_request(const std::shared_ptr<Connection>& connection) {
  connection->timer.expires_after(std::chrono::seconds(10));
  connection->timer.async_wait([connection](const boost::system::error_code& ec) {
    if (ec) return;
    boost::system::error_code ignored;
    connection->socket.close(ignored);
  });
  asio::async_read_until(
      connection->socket, asio::dynamic_buffer(connection->request, max_request_bytes), '\n',
      [connection](const boost::system::error_code& ec, std::size_t length) {
        connection->timer.cancel();
        const auto reply = [connection](std::string answer) {
          auto text = std::make_shared<std::string>(std::move(answer) + "\n");
          asio::async_write(connection->socket, asio::buffer(*text), [connection, text](const boost::system::error_code&, std::size_t) {
            boost::system::error_code ignored;
            connection->socket.shutdown(stream_protocol::socket::shutdown_both, ignored);
          });
        };
        if (ec == asio::error::not_found) return reply(R"({"error":"the request is longer than 1 MiB"})");
        if (ec) return;  // the client went away, or the time-out closed it
        ucred peer{};
        socklen_t size = sizeof peer;
        ::getsockopt(connection->socket.native_handle(), SOL_SOCKET, SO_PEERCRED, &peer, &size);
        ControlRequest request{connection->request.substr(0, length - 1), static_cast<unsigned>(peer.uid), peer.pid};
        connection->request_fn(std::move(request), reply);
      });
}

}  // namespace unima::io
