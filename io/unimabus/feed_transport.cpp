#include "io/unimabus/feed_transport.hpp"

#include <sys/socket.h>

#include <array>
#include <deque>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "config/socket_path.hpp"
#include "platform/peer_warnings.hpp"
#include "unimabus/feed_codec.hpp"
#include "unimabus/line_splitter.hpp"

namespace unima::io {

namespace {
// A client this far behind is dropped rather than buffered without bound (SPEC §6); when
// it comes back its snapshot brings it up to date, so no published value is lost to it.
constexpr std::size_t max_pending_bytes = 1024 * 1024;
}  // namespace

class FeedTransport::Session : public std::enable_shared_from_this<Session> {
 public:
  virtual ~Session() = default;
  virtual void start() = 0;
  virtual void send(std::string_view text) = 0;
  virtual void close() = 0;
};

namespace {

template <typename Socket>
class SocketSession final : public FeedTransport::Session {
 public:
  SocketSession(Socket socket, std::string peer, unimabus::TelegramHandler& on_telegram,
                std::function<void(Session*)> on_closed)
      : socket_(std::move(socket)), peer_(std::move(peer)), on_telegram_(on_telegram), on_closed_(std::move(on_closed)) {}

  void start() override { read(); }

  void send(std::string_view text) override {
    if (closed_) return;
    if (pending_.size() + text.size() > max_pending_bytes) {
      platform::warn_from_peer("feed: clients not reading", peer_,
                               "feed: {} is not reading ({} bytes queued for it); dropping it (it gets a fresh "
                               "snapshot when it reconnects)", peer_, pending_.size() + sending_.size());
      close();
      return;
    }
    pending_.append(text);
    if (!writing_) write();
  }

  void close() override {
    if (closed_) return;
    closed_ = true;
    boost::system::error_code ec;
    socket_.close(ec);
    // Logged like its connect: the first of a peer in a period, then a count; the count of
    // malformed lines as a kind of its own, so that a plain disconnect does not hide it.
    if (malformed_lines_ > 1)
      platform::note_from_peer("feed: disconnections after malformed lines", peer_,
                               "feed: {} disconnected ({} malformed lines, {})", peer_, malformed_lines_,
                               first_malformed_logged_ ? "the first one logged" : "counted with its host's");
    else
      platform::note_from_peer("feed: disconnections", peer_, "feed: {} disconnected", peer_);
    on_closed_(this);
  }

 private:
  void read() {
    auto self = shared_from_this();
    socket_.async_read_some(asio::buffer(in_), [this, self](const boost::system::error_code& ec, std::size_t n) {
      if (ec) return close();
      splitter_.feed(
          std::string_view(in_.data(), n), [this](std::string_view line) { take_line(line); },
          [this] { send(unimabus::format_error("line longer than 64 KiB, dropped")); });
      if (!closed_) read();
    });
  }

  void take_line(std::string_view line) {
    if (line.find_first_not_of(" \t") == std::string_view::npos) return;  // blank lines are harmless
    auto parsed = unimabus::parse_feed_line(line);
    if (auto* error = std::get_if<std::string>(&parsed)) {
      // Every bad line is answered; the log gets the first of each client and the count
      // when it leaves, so a client sending garbage cannot flood it — nor one that
      // reconnects for each line: the first of a host is logged, then a count a minute.
      if (malformed_lines_++ == 0)
        first_malformed_logged_ = platform::warn_from_peer(
            "feed: malformed lines", peer_, "feed: {} sent a malformed line: {} (further ones are counted)", peer_,
            *error);  // escaped with the whole line
      send(unimabus::format_error(*error));
      return;
    }
    const auto refusal = on_telegram_(std::get<unimabus::Telegram>(parsed));
    if (!refusal.empty()) send(unimabus::format_error(refusal));
  }

  void write() {
    writing_ = true;
    sending_.swap(pending_);
    pending_.clear();
    auto self = shared_from_this();
    asio::async_write(socket_, asio::buffer(sending_), [this, self](const boost::system::error_code& ec, std::size_t) {
      writing_ = false;
      if (ec) return close();
      if (!pending_.empty() && !closed_) write();
    });
  }

  Socket socket_;
  std::string peer_;
  unimabus::TelegramHandler& on_telegram_;
  std::function<void(Session*)> on_closed_;
  std::array<char, 8192> in_{};
  unimabus::LineSplitter splitter_;
  std::string pending_;
  std::string sending_;
  bool writing_ = false;
  bool closed_ = false;
  std::uint64_t malformed_lines_ = 0;
  bool first_malformed_logged_ = false;
};

}  // namespace

FeedTransport::FeedTransport(asio::io_context& io, const config::ListenEndpoint& listen, unsigned max_clients,
                             unimabus::TelegramHandler on_telegram, SnapshotFn snapshot)
    : io_(io),
      listen_(listen.text),
      max_clients_(max_clients),
      on_telegram_(std::move(on_telegram)),
      snapshot_(std::move(snapshot)) {
  if (listen.is_unix()) {
    unix_path_ = listen.unix_path;
    config::clear_socket_path(unix_path_, "unimabus.listen");  // a previous run's socket file would block the bind
    unix_acceptor_ = std::make_unique<asio::local::stream_protocol::acceptor>(
        io_, asio::local::stream_protocol::endpoint(unix_path_));
    unix_accepting_ = std::make_unique<RetryingAcceptor<asio::local::stream_protocol::acceptor>>(
        *unix_acceptor_, "feed", [this](asio::local::stream_protocol::socket socket) { accepted(std::move(socket)); });
    return;
  }
  // The loader checked the address (config/endpoint): `unima-bridge check` refuses what
  // this would.
  const asio::ip::tcp::endpoint endpoint(asio::ip::make_address(listen.tcp.host), listen.tcp.port);
  tcp_acceptor_ = std::make_unique<asio::ip::tcp::acceptor>(io_);
  tcp_acceptor_->open(endpoint.protocol());
  tcp_acceptor_->set_option(asio::ip::tcp::acceptor::reuse_address(true));
  tcp_acceptor_->bind(endpoint);
  tcp_acceptor_->listen();
  tcp_accepting_ = std::make_unique<RetryingAcceptor<asio::ip::tcp::acceptor>>(
      *tcp_acceptor_, "feed", [this](asio::ip::tcp::socket socket) { accepted(std::move(socket)); });
}

FeedTransport::~FeedTransport() { stop(); }

std::uint16_t FeedTransport::port() const {
  boost::system::error_code ec;
  return tcp_acceptor_ ? tcp_acceptor_->local_endpoint(ec).port() : 0;
}

void FeedTransport::start() {
  if (tcp_acceptor_) {
    spdlog::info("feed: listening on {}:{}", listen_.substr(0, listen_.rfind(':')), port());
    tcp_accepting_->start();
  } else {
    spdlog::info("feed: listening on {}", listen_);
    unix_accepting_->start();
  }
}

void FeedTransport::stop() {
  if (stopped_) return;
  stopped_ = true;
  boost::system::error_code ec;
  if (tcp_accepting_) tcp_accepting_->stop();
  if (unix_accepting_) unix_accepting_->stop();
  if (tcp_acceptor_) tcp_acceptor_->close(ec);
  if (unix_acceptor_) {
    unix_acceptor_->close(ec);
    config::remove_socket_file(unix_path_);
  }
  for (const auto& s : sessions_.take_all()) s->close();
}

void FeedTransport::publish(banks::BankId bank, std::uint16_t offset, std::uint16_t value) {
  if (sessions_.empty()) return;
  const auto line = unimabus::format_change(bank, offset, value);
  // Copy first: a session that is too slow closes itself and leaves the set.
  for (const auto& s : sessions_.copy()) s->send(line);
}

void FeedTransport::adopt(std::shared_ptr<Session> session) {
  sessions_.add(session);
  session->send(snapshot_());
  session->start();
}

namespace {
std::string describe_peer(const asio::ip::tcp::socket& socket, const std::string&) {
  boost::system::error_code ec;
  const auto remote = socket.remote_endpoint(ec);
  return ec ? std::string("?") : remote.address().to_string() + ":" + std::to_string(remote.port());
}
// A unix-socket client has no address: it is told apart by its user (SO_PEERCRED), so the
// per-peer limits of the log (platform/peer_warnings) count per user. Not per process: a
// driver that restarts, or a script that connects once per value, is a new process each
// time and would be a new peer each time, limited never; the user is what the socket's
// mode (0660, its group) let in, as an address is what a TCP listener lets in.
std::string describe_peer(asio::local::stream_protocol::socket& socket, const std::string& listen) {
  ucred credentials{};
  socklen_t size = sizeof credentials;
  if (::getsockopt(socket.native_handle(), SOL_SOCKET, SO_PEERCRED, &credentials, &size) != 0) return listen;
  return fmt::format("{} uid {}", listen, credentials.uid);
}

// Changes go out one small line at a time (a captured value, a W write) and a driver waits
// for each: Nagle's algorithm would hold a line until the previous one is acknowledged.
void send_at_once(asio::ip::tcp::socket& socket) {
  boost::system::error_code ec;
  socket.set_option(asio::ip::tcp::no_delay(true), ec);
}
void send_at_once(asio::local::stream_protocol::socket&) {}
}  // namespace

template <typename Socket>
void FeedTransport::accepted(Socket socket) {
  auto peer = describe_peer(socket, listen_);
  if (sessions_.size() >= max_clients_) {
    // Told why, then closed: the descriptors a burst of connections takes come back at once,
    // so the Modbus side never runs short of them.
    boost::system::error_code ignored;
    const auto refusal = unimabus::format_error(fmt::format("too many feed clients ({} connected)", sessions_.size()));
    socket.non_blocking(true, ignored);  // a fresh socket's buffer takes one line; never wait for it
    asio::write(socket, asio::buffer(refusal), ignored);
    socket.close(ignored);
    if (refused_++ == 0)
      spdlog::warn("feed: refusing {} and any further client: {} are connected (unimabus.max_clients)", peer,
                   max_clients_);
    return;
  }
  send_at_once(socket);
  // A client that reconnects in a loop must not flood the log: the first connect of a
  // host (or unix user) in a period is logged, then how many more.
  platform::note_from_peer("feed: connections", peer, "feed: {} connected", peer);
  adopt(std::make_shared<SocketSession<Socket>>(std::move(socket), std::move(peer), on_telegram_,
                                                [this](Session* s) { forget(s); }));
}

void FeedTransport::forget(Session* session) {
  sessions_.forget(session);
  if (refused_ > 0 && sessions_.size() < max_clients_) {
    spdlog::info("feed: accepting clients again ({} refused meanwhile)", refused_);
    refused_ = 0;
  }
}

}  // namespace unima::io
