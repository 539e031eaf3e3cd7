// Load for Modbus/TCP Security (issue 18, docs/performance.md): the same client over plain
// TCP or TLS, so that the daemon's TLS figures are a ratio of its plain ones measured by
// one client. One thread, Asio; every loop bounded by --duration.
//
//   unima-bench-tls-load --port N [--tls CA CERT KEY] [--mode requests|handshakes]
//                        [--connections 8] [--duration 3] [--address 4352] [--quantity 64]
//
// requests:   each connection sends FC4 × quantity, one request in flight, and checks the
//             answer; prints {"rps":…,"p50_us":…,"p99_us":…}.
// handshakes: each connection loops connect → full handshake (no session resumption) →
//             one FC4 → close; prints {"handshakes_per_s":…,"p50_ms":…,"p99_ms":…}.

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "platform/asio_ssl.hpp"

namespace {

using namespace unima;
using asio::ip::tcp;
using Clock = std::chrono::steady_clock;

struct Options {
  std::uint16_t port = 0;
  std::optional<std::array<std::string, 3>> tls;  // CA, certificate, key
  bool handshakes = false;
  int connections = 8;
  double duration = 3;
  std::uint16_t address = 4352;
  std::uint16_t quantity = 64;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto next = [&] {
      if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
      return std::string(argv[++i]);
    };
    if (a == "--port") o.port = static_cast<std::uint16_t>(std::stoi(next()));
    else if (a == "--tls") o.tls = std::array{next(), next(), next()};
    else if (a == "--mode") o.handshakes = next() == "handshakes";
    else if (a == "--connections") o.connections = std::stoi(next());
    else if (a == "--duration") o.duration = std::stod(next());
    else if (a == "--address") o.address = static_cast<std::uint16_t>(std::stoi(next()));
    else if (a == "--quantity") o.quantity = static_cast<std::uint16_t>(std::stoi(next()));
    else throw std::runtime_error("unknown option " + a);
  }
  if (o.port == 0) throw std::runtime_error("--port is required");
  return o;
}

// One client connection, plain or TLS; the stream type is chosen at run time.
class Client : public std::enable_shared_from_this<Client> {
 public:
  struct Shared {
    const Options& options;
    asio::ssl::context* tls;
    Clock::time_point until;
    std::vector<double> latencies;  // µs per request, or ms per handshake
    std::uint64_t done = 0;
    std::string error;
  };

  Client(asio::io_context& io, Shared& shared) : io_(io), shared_(shared) {
    const auto& o = shared.options;
    request_ = {0, 0, 0, 0, 0, 6, 1, 4, static_cast<std::uint8_t>(o.address >> 8), static_cast<std::uint8_t>(o.address),
                static_cast<std::uint8_t>(o.quantity >> 8), static_cast<std::uint8_t>(o.quantity)};
    answer_.resize(9 + 2 * std::size_t{o.quantity});
  }

  void start() { connect(); }

 private:
  void connect() {
    if (Clock::now() >= shared_.until) return;
    socket_.emplace(io_);
    if (shared_.tls) stream_.emplace(*socket_, *shared_.tls);
    connected_at_ = Clock::now();
    socket_->async_connect(tcp::endpoint(asio::ip::address_v4::loopback(), shared_.options.port),
                           [this, self = shared_from_this()](const boost::system::error_code& ec) {
                             if (ec) return fail("connect: " + ec.message());
                             socket_->set_option(tcp::no_delay(true));
                             if (!stream_) return send();
                             stream_->async_handshake(asio::ssl::stream_base::client,
                                                      [this, self](const boost::system::error_code& ec) {
                                                        if (ec) return fail("handshake: " + ec.message());
                                                        send();
                                                      });
                           });
  }

  void send() {
    ++transaction_;
    request_[0] = static_cast<std::uint8_t>(transaction_ >> 8);
    request_[1] = static_cast<std::uint8_t>(transaction_);
    sent_at_ = Clock::now();
    auto on_sent = [this, self = shared_from_this()](const boost::system::error_code& ec, std::size_t) {
      if (ec) return fail("write: " + ec.message());
      receive();
    };
    if (stream_) asio::async_write(*stream_, asio::buffer(request_), on_sent);
    else asio::async_write(*socket_, asio::buffer(request_), on_sent);
  }

  void receive() {
    auto on_read = [this, self = shared_from_this()](const boost::system::error_code& ec, std::size_t) {
      if (ec) return fail("read: " + ec.message());
      const auto& o = shared_.options;
      if (answer_[0] != request_[0] || answer_[1] != request_[1] || answer_[7] != 4 || answer_[8] != 2 * o.quantity)
        return fail("a wrong answer");
      const auto now = Clock::now();
      if (o.handshakes) {
        shared_.latencies.push_back(std::chrono::duration<double, std::milli>(now - connected_at_).count());
        ++shared_.done;
        boost::system::error_code ignored;
        socket_->close(ignored);
        stream_.reset();
        return connect();
      }
      shared_.latencies.push_back(std::chrono::duration<double, std::micro>(now - sent_at_).count());
      ++shared_.done;
      if (now < shared_.until) send();
    };
    if (stream_) asio::async_read(*stream_, asio::buffer(answer_), on_read);
    else asio::async_read(*socket_, asio::buffer(answer_), on_read);
  }

  void fail(const std::string& why) {
    if (shared_.error.empty()) shared_.error = why;
    io_.stop();
  }

  asio::io_context& io_;
  Shared& shared_;
  std::optional<tcp::socket> socket_;
  std::optional<asio::ssl::stream<tcp::socket&>> stream_;
  std::vector<std::uint8_t> request_;
  std::vector<std::uint8_t> answer_;
  std::uint16_t transaction_ = 0;
  Clock::time_point sent_at_, connected_at_;
};

double percentile(std::vector<double>& values, double p) {
  if (values.empty()) return 0;
  const auto at = static_cast<std::size_t>(p * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(at), values.end());
  return values[at];
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const auto options = parse(argc, argv);
    asio::io_context io;
    std::optional<asio::ssl::context> tls;
    if (options.tls) {
      tls.emplace(asio::ssl::context::tls_client);
      tls->load_verify_file((*options.tls)[0]);
      tls->use_certificate_chain_file((*options.tls)[1]);
      tls->use_private_key_file((*options.tls)[2], asio::ssl::context::pem);
      tls->set_verify_mode(asio::ssl::verify_peer);
      SSL_CTX_set_session_cache_mode(tls->native_handle(), SSL_SESS_CACHE_OFF);
      SSL_CTX_set_options(tls->native_handle(), SSL_OP_NO_TICKET);
    }
    const auto start = Clock::now();
    Client::Shared shared{options, tls ? &*tls : nullptr,
                          start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options.duration)),
                          {}, 0, {}};
    for (int i = 0; i < options.connections; ++i) std::make_shared<Client>(io, shared)->start();
    io.run();
    if (!shared.error.empty()) {
      std::fprintf(stderr, "unima-bench-tls-load: %s\n", shared.error.c_str());
      return 1;
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    const double rate = static_cast<double>(shared.done) / seconds;
    const double p50 = percentile(shared.latencies, 0.5), p99 = percentile(shared.latencies, 0.99);
    if (options.handshakes)
      std::printf("{\"handshakes_per_s\":%.1f,\"p50_ms\":%.3f,\"p99_ms\":%.3f,\"connections\":%d}\n", rate, p50, p99,
                  options.connections);
    else
      std::printf("{\"rps\":%.1f,\"p50_us\":%.1f,\"p99_us\":%.1f,\"connections\":%d,\"tls\":%s}\n", rate, p50, p99,
                  options.connections, options.tls ? "true" : "false");
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "unima-bench-tls-load: %s\n", e.what());
    return 1;
  }
}
