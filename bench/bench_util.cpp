#include "bench/bench_util.hpp"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace unima::bench {

std::uint64_t now_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::uint64_t>(ts.tv_sec) * 1'000'000'000u + static_cast<std::uint64_t>(ts.tv_nsec);
}

int connect_tcp(const std::string& host, std::uint16_t port) {
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  if (::inet_pton(AF_INET, host.c_str(), &addr.sin_addr) != 1)
    throw std::runtime_error("not an IPv4 address: " + host);
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) throw std::runtime_error(std::string("socket: ") + std::strerror(errno));
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    const int error = errno;
    ::close(fd);
    throw std::runtime_error("connect to " + host + ":" + std::to_string(port) + ": " + std::strerror(error));
  }
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  return fd;
}

void send_all(int fd, std::span<const std::uint8_t> bytes) {
  while (!bytes.empty()) {
    const auto n = ::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw std::runtime_error(std::string("send: ") + std::strerror(errno));
    bytes = bytes.subspan(static_cast<std::size_t>(n));
  }
}

bool receive_exactly(int fd, std::span<std::uint8_t> out, int timeout_ms) {
  const auto deadline = now_ns() + static_cast<std::uint64_t>(timeout_ms) * 1'000'000u;
  std::size_t got = 0;
  while (got < out.size()) {
    const auto now = now_ns();
    if (now >= deadline) return false;
    pollfd p{fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>((deadline - now) / 1'000'000u) + 1);
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) return false;
    const auto n = ::recv(fd, out.data() + got, out.size() - got, 0);
    if (n <= 0) return false;
    got += static_cast<std::size_t>(n);
  }
  return true;
}

Percentiles percentiles(std::vector<std::uint32_t>& samples_ns) {
  Percentiles p;
  if (samples_ns.empty()) return p;
  std::sort(samples_ns.begin(), samples_ns.end());
  const auto at = [&](double q) {
    const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(samples_ns.size())));
    return samples_ns[std::clamp<std::size_t>(rank, 1, samples_ns.size()) - 1] / 1000.0;
  };
  p.p50 = at(0.50);
  p.p99 = at(0.99);
  p.p999 = at(0.999);
  p.max = samples_ns.back() / 1000.0;
  return p;
}

Args::Args(int argc, char** argv, const std::map<std::string, std::string>& defaults, const std::string& usage)
    : values_(defaults) {
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::fputs(usage.c_str(), stdout);
      std::exit(0);
    }
    if (!arg.starts_with("--")) throw std::runtime_error("unexpected argument '" + arg + "'\n" + usage);
    arg = arg.substr(2);
    std::string value;
    if (const auto eq = arg.find('='); eq != std::string::npos) {
      value = arg.substr(eq + 1);
      arg = arg.substr(0, eq);
    } else if (defaults.contains(arg) && defaults.at(arg) == "false") {
      value = "true";  // a flag
    } else if (i + 1 < argc) {
      value = argv[++i];
    } else {
      throw std::runtime_error("--" + arg + " needs a value\n" + usage);
    }
    if (!defaults.contains(arg)) throw std::runtime_error("unknown option --" + arg + "\n" + usage);
    values_[arg] = value;
  }
}

const std::string& Args::text(const std::string& name) const { return values_.at(name); }

std::uint64_t Args::number(const std::string& name) const {
  const auto& value = text(name);
  char* end = nullptr;
  errno = 0;
  const auto n = std::strtoull(value.c_str(), &end, 0);
  if (value.empty() || *end != '\0' || errno != 0 || value[0] == '-')
    throw std::runtime_error("--" + name + ": not a number: '" + value + "'");
  return n;
}

double Args::real(const std::string& name) const {
  const auto& value = text(name);
  char* end = nullptr;
  const double d = std::strtod(value.c_str(), &end);
  if (value.empty() || *end != '\0' || d < 0) throw std::runtime_error("--" + name + ": not a number: '" + value + "'");
  return d;
}

}  // namespace unima::bench
