// foreign-slave-sim: the foreign Modbus slaves of seeds 000, 001 and 002, as the bridge
// meets them in master mode, on a pseudo-terminal (RTU) and on TCP, for the integration
// tests and the benchmark. Each slave serves its device profile's map; switches make one
// dead, slow or answering garbage, at start or at run time through a control socket.
//
//   foreign-slave-sim [--pty LINK] [--baud N] [--tcp PORT] [--frames FILE] [--control PATH]
//                     --slave ADDR=PROFILE[,dead][,slow=MS][,garbage=KIND][,exception=CODE] ...
//
// KIND: crc, short, function, address, noise. On start it prints "ready pty=LINK tcp=PORT".
// --frames logs every frame heard and sent: "<monotonic µs> rx|tx rtu|tcp <hex bytes>".
// --baud N: the pty carries a frame at once, so the simulator plays the wire of a line at N
// baud, 8N1: an RTU answer leaves when, on that line, the request would have been carried
// (its bytes × 10 bits ÷ N), the slave had heard its t3.5 of silence, waited its `slow`
// and sent its answer's bytes — so "rx" is logged when the request begins on the wire and
// "tx" when the answer has ended there. Without it an answer leaves after `slow` alone.
// Control lines: "dead A on|off", "slow A MS", "garbage A KIND|off", "exception A CODE|off",
// "set A REG VALUE", "get A REG", "input A REG 0|1", "coil A REG", "count A", "reset";
// answered by one line.

#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/pseudo_terminal.hpp"
#include "modbus/rtu/crc16.hpp"
#include "modbus/rtu/rtu_adu.hpp"
#include "modbus/rtu/rtu_timing.hpp"
#include "modbus/mbap.hpp"
#include "tests/sim/foreign_slave.hpp"

namespace {

using unima::sim::Bytes;
using Clock = std::chrono::steady_clock;

enum class Garbage { off, crc, short_frame, function, address, noise };

struct Behaviour {
  bool dead = false;
  std::chrono::milliseconds slow{0};
  Garbage garbage = Garbage::off;
  std::uint8_t exception = 0;
};

struct Slave {
  std::unique_ptr<unima::sim::ForeignSlave> model;
  Behaviour behaviour;
  std::uint64_t requests = 0;
};

struct Pending {
  Clock::time_point at;
  int fd;
  bool rtu;
  Bytes bytes;
};

struct Client {
  int fd;
  Bytes in;
};

std::map<std::uint8_t, Slave> slaves;
std::vector<Pending> pending;
std::FILE* frames = nullptr;
std::optional<unima::modbus::RtuTiming> line_timing;  // --baud: the wire to play
std::uint32_t noise_state = 12345;
volatile sig_atomic_t stop_requested = 0;

[[noreturn]] void die(const std::string& message) {
  std::fprintf(stderr, "foreign-slave-sim: %s\n", message.c_str());
  std::exit(2);
}

std::optional<Garbage> parse_garbage(const std::string& s) {
  if (s == "off") return Garbage::off;
  if (s == "crc") return Garbage::crc;
  if (s == "short") return Garbage::short_frame;
  if (s == "function") return Garbage::function;
  if (s == "address") return Garbage::address;
  if (s == "noise") return Garbage::noise;
  return std::nullopt;
}

void log_frame(const char* direction, bool rtu, std::span<const std::uint8_t> bytes) {
  if (!frames) return;
  const auto us = std::chrono::duration_cast<std::chrono::microseconds>(Clock::now().time_since_epoch()).count();
  std::string line = std::to_string(us) + " " + direction + (rtu ? " rtu" : " tcp");
  char hex[4];
  for (auto b : bytes) {
    std::snprintf(hex, sizeof hex, " %02X", b);
    line += hex;
  }
  line += "\n";
  std::fputs(line.c_str(), frames);
  std::fflush(frames);
}

void write_all(int fd, const Bytes& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const auto n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EAGAIN) {
      pollfd p{fd, POLLOUT, 0};
      ::poll(&p, 1, 100);
      continue;
    }
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}

Bytes rtu_frame(std::uint8_t address, const Bytes& pdu) {
  Bytes frame(pdu.size() + 3);
  unima::modbus::write_rtu_adu(address, pdu, frame);
  return frame;
}

Bytes tcp_adu(std::uint16_t transaction, std::uint8_t unit, const Bytes& pdu) {
  Bytes adu(unima::modbus::mbap_header_size + pdu.size());
  unima::modbus::write_tcp_adu(transaction, unit, pdu, adu);
  return adu;
}

// The response as a misbehaving slave would send it instead of the good one.
Bytes spoil(const Behaviour& b, bool rtu, std::uint8_t address, Bytes pdu, std::uint16_t transaction) {
  const auto frame = [&](std::uint8_t addr, const Bytes& p) { return rtu ? rtu_frame(addr, p) : tcp_adu(transaction, addr, p); };
  switch (b.garbage) {
    case Garbage::off: return frame(address, pdu);
    case Garbage::crc: {
      auto f = frame(address, pdu);
      if (rtu) f.back() ^= 0x5A;
      else f[2] = 0x12;  // TCP has no CRC: a protocol id that is not Modbus
      return f;
    }
    case Garbage::short_frame: {
      auto f = frame(address, pdu);
      f.resize(rtu ? 4 : unima::modbus::mbap_header_size + 1);
      return f;
    }
    case Garbage::function: pdu[0] = static_cast<std::uint8_t>(pdu[0] + 1); return frame(address, pdu);
    case Garbage::address: return frame(static_cast<std::uint8_t>(address + 1), pdu);
    case Garbage::noise: {
      Bytes noise(7);
      for (auto& n : noise) {
        noise_state = noise_state * 1103515245u + 12345u;
        n = static_cast<std::uint8_t>(noise_state >> 16);
      }
      return noise;
    }
  }
  return {};
}

// A request PDU for `address` arrived; queues what the slave says, if anything.
void serve(int fd, bool rtu, std::uint8_t address, std::span<const std::uint8_t> pdu, std::uint16_t transaction) {
  const auto it = slaves.find(address);
  if (it == slaves.end()) {
    if (!rtu) {  // a TCP gateway answers for units it does not know
      const Bytes reply{static_cast<std::uint8_t>(pdu[0] | 0x80), 0x0B};
      pending.push_back({Clock::now(), fd, rtu, tcp_adu(transaction, address, reply)});
    }
    return;
  }
  auto& slave = it->second;
  ++slave.requests;
  if (slave.behaviour.dead) return;
  Bytes reply = slave.behaviour.exception ? Bytes{static_cast<std::uint8_t>(pdu[0] | 0x80), slave.behaviour.exception}
                                          : slave.model->answer(pdu);
  if (address == 0) return;  // broadcast: no answer
  auto answer = spoil(slave.behaviour, rtu, address, reply, transaction);
  auto at = Clock::now() + slave.behaviour.slow;
  if (rtu && line_timing) {
    const auto wire = [](std::size_t bytes) { return line_timing->character * static_cast<long>(bytes); };
    at += wire(pdu.size() + 3) + line_timing->frame_gap + wire(answer.size());
  }
  pending.push_back({at, fd, rtu, std::move(answer)});
}

// RTU: a request's length from its first bytes (Modbus over Serial Line V1.02 §2.5.1.1).
std::optional<std::size_t> request_length(const Bytes& b) {
  if (b.size() < 2) return std::nullopt;
  const auto fn = b[1];
  if (fn >= 1 && fn <= 6) return 8;
  if (fn == 15 || fn == 16) {
    if (b.size() < 7) return std::nullopt;
    return 9 + std::size_t{b[6]};
  }
  return std::nullopt;
}

void rtu_frames(int fd, Bytes& in, bool silence) {
  while (!in.empty()) {
    const auto length = request_length(in);
    if (!length) {
      if (!silence) return;
      log_frame("rx", true, in);  // garbage, ended by silence
      in.clear();
      return;
    }
    if (in.size() < *length) {
      if (!silence) return;
      log_frame("rx", true, in);
      in.clear();
      return;
    }
    const std::span<const std::uint8_t> frame(in.data(), *length);
    log_frame("rx", true, frame);
    const auto crc = static_cast<std::uint16_t>(frame[*length - 2] | frame[*length - 1] << 8);
    if (unima::modbus::crc16(frame.first(*length - 2)) == crc)  // a bad CRC gets no answer
      serve(fd, true, frame[0], frame.subspan(1, *length - 3), 0);
    in.erase(in.begin(), in.begin() + static_cast<std::ptrdiff_t>(*length));
  }
}

bool tcp_frames(Client& c) {
  while (true) {
    const auto adu = unima::modbus::parse_tcp_adu(c.in);
    if (adu.status == unima::modbus::TcpAdu::Status::bad_header) return false;
    if (adu.status == unima::modbus::TcpAdu::Status::need_more) return true;
    log_frame("rx", false, std::span(c.in.data(), adu.size));
    serve(c.fd, false, adu.header.unit_id, adu.pdu, adu.header.transaction_id);
    c.in.erase(c.in.begin(), c.in.begin() + static_cast<std::ptrdiff_t>(adu.size));
  }
}

std::string control(const std::string& line) {
  std::istringstream in(line);
  std::string command;
  unsigned address = 0;
  in >> command;
  if (command == "reset") {
    for (auto& [a, s] : slaves) s.requests = 0;
    return "ok";
  }
  in >> address;
  const auto it = slaves.find(static_cast<std::uint8_t>(address));
  if (it == slaves.end()) return "error: no slave " + std::to_string(address);
  auto& slave = it->second;
  std::string arg;
  if (command == "dead") {
    in >> arg;
    slave.behaviour.dead = arg == "on";
  } else if (command == "slow") {
    long ms = 0;
    in >> ms;
    slave.behaviour.slow = std::chrono::milliseconds(ms);
  } else if (command == "garbage") {
    in >> arg;
    const auto g = parse_garbage(arg);
    if (!g) return "error: garbage is off, crc, short, function, address or noise";
    slave.behaviour.garbage = *g;
  } else if (command == "exception") {
    in >> arg;
    slave.behaviour.exception = arg == "off" ? 0 : static_cast<std::uint8_t>(std::stoul(arg, nullptr, 0));
  } else if (command == "set") {
    unsigned reg = 0, value = 0;
    in >> reg >> value;
    if (!slave.model->set_holding(static_cast<std::uint16_t>(reg), static_cast<std::uint16_t>(value)))
      return "error: no register " + std::to_string(reg);
  } else if (command == "get") {
    unsigned reg = 0;
    in >> reg;
    const auto v = slave.model->holding(static_cast<std::uint16_t>(reg));
    return v ? "value " + std::to_string(*v) : "error: no register " + std::to_string(reg);
  } else if (command == "input") {
    unsigned reg = 0, value = 0;
    in >> reg >> value;
    if (!slave.model->set_input(static_cast<std::uint16_t>(reg), value != 0))
      return "error: no input " + std::to_string(reg);
  } else if (command == "coil") {
    unsigned reg = 0;
    in >> reg;
    const auto v = slave.model->coil(static_cast<std::uint16_t>(reg));
    return v ? std::string("coil ") + (*v ? "1" : "0") : "error: no coil " + std::to_string(reg);
  } else if (command == "count") {
    return "count " + std::to_string(slave.requests);
  } else {
    return "error: unknown command '" + command + "'";
  }
  return "ok";
}

void add_slave(const std::string& spec) {
  const auto eq = spec.find('=');
  if (eq == std::string::npos) die("--slave ADDR=PROFILE[,options]: " + spec);
  const auto address = std::stoul(spec.substr(0, eq));
  std::vector<std::string> parts;
  std::stringstream rest(spec.substr(eq + 1));
  for (std::string part; std::getline(rest, part, ',');) parts.push_back(part);
  const auto* profile = unima::master::find_profile(parts.at(0));
  if (!profile) die("unknown profile '" + parts.at(0) + "'");
  Slave slave;
  slave.model = std::make_unique<unima::sim::ForeignSlave>(*profile);
  for (std::size_t i = 1; i < parts.size(); ++i) {
    const auto& p = parts[i];
    if (p == "dead") slave.behaviour.dead = true;
    else if (p.starts_with("slow=")) slave.behaviour.slow = std::chrono::milliseconds(std::stol(p.substr(5)));
    else if (p.starts_with("garbage=")) {
      const auto g = parse_garbage(p.substr(8));
      if (!g) die("unknown garbage '" + p.substr(8) + "'");
      slave.behaviour.garbage = *g;
    } else if (p.starts_with("exception=")) slave.behaviour.exception = static_cast<std::uint8_t>(std::stoul(p.substr(10), nullptr, 0));
    else die("unknown slave option '" + p + "'");
  }
  slaves[static_cast<std::uint8_t>(address)] = std::move(slave);
}

int listen_tcp(std::uint16_t& port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  const int one = 1;
  ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 || ::listen(fd, 16) != 0)
    die("cannot listen on 127.0.0.1:" + std::to_string(port) + ": " + std::strerror(errno));
  socklen_t len = sizeof addr;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  port = ntohs(addr.sin_port);
  return fd;
}

int listen_unix(const std::string& path) {
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::strncpy(addr.sun_path, path.c_str(), sizeof addr.sun_path - 1);
  ::unlink(path.c_str());
  if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 || ::listen(fd, 4) != 0)
    die("cannot listen on " + path + ": " + std::strerror(errno));
  return fd;
}

}  // namespace

int main(int argc, char** argv) {
  std::string pty_link, frames_path, control_path;
  std::optional<std::uint16_t> tcp_port;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) die(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--pty") pty_link = value();
    else if (arg == "--baud") line_timing = unima::modbus::rtu_timing(static_cast<unsigned>(std::stoul(value())), false, 1);
    else if (arg == "--tcp") tcp_port = static_cast<std::uint16_t>(std::stoul(value()));
    else if (arg == "--frames") frames_path = value();
    else if (arg == "--control") control_path = value();
    else if (arg == "--slave") add_slave(value());
    else die("unknown argument '" + arg + "'");
  }
  if (slaves.empty()) die("no --slave given");
  if (pty_link.empty() && !tcp_port) die("give --pty LINK, --tcp PORT or both");
  ::signal(SIGPIPE, SIG_IGN);
  ::signal(SIGTERM, [](int) { stop_requested = 1; });
  ::signal(SIGINT, [](int) { stop_requested = 1; });
  if (!frames_path.empty()) frames = std::fopen(frames_path.c_str(), "w");

  int pty_master = -1, pty_slave = -1;
  if (!pty_link.empty()) {
    try {
      const auto pty = unima::test_support::open_raw_pseudo_terminal();
      pty_master = pty.master;
      pty_slave = pty.slave;
      ::fcntl(pty_master, F_SETFL, ::fcntl(pty_master, F_GETFL) | O_NONBLOCK);
      unima::test_support::point_link_at(pty_link, pty.name);
    } catch (const std::exception& e) {
      die(std::string("the line at ") + pty_link + ": " + e.what());
    }
    // pty_slave stays open, so that the master side keeps working while the bridge reopens.
  }
  int tcp_listener = -1;
  if (tcp_port) tcp_listener = listen_tcp(*tcp_port);
  int control_listener = control_path.empty() ? -1 : listen_unix(control_path);

  std::printf("ready pty=%s tcp=%u\n", pty_link.c_str(), tcp_port ? unsigned{*tcp_port} : 0u);
  std::fflush(stdout);

  Bytes rtu_in;
  Clock::time_point rtu_last_byte{};
  std::vector<Client> clients, controls;
  constexpr auto rtu_silence = std::chrono::milliseconds(20);
  while (!stop_requested) {
    std::vector<pollfd> fds;
    if (pty_master >= 0) fds.push_back({pty_master, POLLIN, 0});
    if (tcp_listener >= 0) fds.push_back({tcp_listener, POLLIN, 0});
    if (control_listener >= 0) fds.push_back({control_listener, POLLIN, 0});
    for (const auto& c : clients) fds.push_back({c.fd, POLLIN, 0});
    for (const auto& c : controls) fds.push_back({c.fd, POLLIN, 0});
    auto wake = Clock::now() + std::chrono::milliseconds(200);
    for (const auto& p : pending) wake = std::min(wake, p.at);
    if (!rtu_in.empty()) wake = std::min(wake, rtu_last_byte + rtu_silence);
    // To the microsecond, not poll's millisecond: an answer's time is what --baud plays.
    const auto wait = std::max(std::chrono::nanoseconds(0), std::chrono::ceil<std::chrono::nanoseconds>(wake - Clock::now()));
    const timespec timeout{static_cast<time_t>(wait.count() / 1'000'000'000), static_cast<long>(wait.count() % 1'000'000'000)};
    ::ppoll(fds.data(), fds.size(), &timeout, nullptr);
    const auto now = Clock::now();

    std::uint8_t buf[4096];
    for (const auto& p : fds) {
      if (!(p.revents & (POLLIN | POLLHUP | POLLERR))) continue;
      if (p.fd == pty_master) {
        const auto n = ::read(pty_master, buf, sizeof buf);
        if (n > 0) {
          rtu_in.insert(rtu_in.end(), buf, buf + n);
          rtu_last_byte = now;
          rtu_frames(pty_master, rtu_in, false);
        }
      } else if (p.fd == tcp_listener) {
        const int fd = ::accept4(tcp_listener, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (fd >= 0) {
          const int one = 1;
          ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
          clients.push_back({fd, {}});
        }
      } else if (p.fd == control_listener) {
        const int fd = ::accept4(control_listener, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (fd >= 0) controls.push_back({fd, {}});
      }
    }
    for (auto* list : {&clients, &controls}) {
      for (auto it = list->begin(); it != list->end();) {
        const bool ready = std::any_of(fds.begin(), fds.end(), [&](const pollfd& p) {
          return p.fd == it->fd && (p.revents & (POLLIN | POLLHUP | POLLERR));
        });
        bool keep = true;
        if (ready) {
          const auto n = ::read(it->fd, buf, sizeof buf);
          if (n <= 0) keep = false;
          else {
            it->in.insert(it->in.end(), buf, buf + n);
            if (list == &clients) {
              keep = tcp_frames(*it);
            } else {
              for (auto nl = std::find(it->in.begin(), it->in.end(), '\n'); nl != it->in.end();
                   nl = std::find(it->in.begin(), it->in.end(), '\n')) {
                const std::string line(it->in.begin(), nl);
                it->in.erase(it->in.begin(), nl + 1);
                const auto reply = control(line) + "\n";
                write_all(it->fd, Bytes(reply.begin(), reply.end()));
              }
            }
          }
        }
        if (!keep) {
          std::erase_if(pending, [&](const Pending& q) { return q.fd == it->fd; });
          ::close(it->fd);
          it = list->erase(it);
        } else {
          ++it;
        }
      }
    }
    if (!rtu_in.empty() && now - rtu_last_byte >= rtu_silence) rtu_frames(pty_master, rtu_in, true);
    for (auto it = pending.begin(); it != pending.end();) {
      if (it->at > Clock::now()) {
        ++it;
        continue;
      }
      log_frame("tx", it->rtu, it->bytes);
      write_all(it->fd, it->bytes);
      it = pending.erase(it);
    }
  }
  if (!pty_link.empty()) ::unlink(pty_link.c_str());
  if (!control_path.empty()) ::unlink(control_path.c_str());
  if (pty_slave >= 0) ::close(pty_slave);
  return 0;
}
