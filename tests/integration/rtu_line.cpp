#include "tests/integration/rtu_line.hpp"

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <stdexcept>

#include "modbus/rtu/rtu_adu.hpp"

#include "tests/support/pseudo_terminal.hpp"

namespace unima::test {

namespace fs = std::filesystem;

Bytes rtu_adu(std::uint8_t address, const Bytes& pdu) {
  Bytes out(pdu.size() + 3);
  out.resize(modbus::write_rtu_adu(address, pdu, out));
  return out;
}

PtyLine::PtyLine(fs::path link) : link_(std::move(link)) { open_terminal(); }

PtyLine::~PtyLine() {
  close_terminal();
  std::error_code ec;
  fs::remove(link_, ec);
}

void PtyLine::open_terminal() {
  const auto pty = test_support::open_raw_pseudo_terminal();
  master_ = pty.master;
  slave_ = pty.slave;
  test_support::point_link_at(link_, pty.name);
}

void PtyLine::close_terminal() {
  if (master_ >= 0) ::close(master_);
  if (slave_ >= 0) ::close(slave_);
  master_ = slave_ = -1;
}

// The link goes too, as a device node does: /dev/pts/N is free for the next terminal
// anyone opens, and the daemon must not find another test's line behind a stale link.
void PtyLine::hang_up() {
  close_terminal();
  std::error_code ec;
  fs::remove(link_, ec);
}

void PtyLine::replace() {
  close_terminal();
  open_terminal();
}

void PtyLine::write(const Bytes& bytes) const {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const auto n = ::write(master_, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw std::runtime_error("write to the pseudo-terminal failed");
    done += static_cast<std::size_t>(n);
  }
}

Bytes PtyLine::read(std::size_t n, std::chrono::milliseconds timeout) const {
  Bytes out;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::uint8_t buf[512];
  while (out.size() < n) {
    // read_before looks at least once, so that a time-out of 0 takes what is there.
    const auto got = read_before(master_, deadline, std::span(buf, std::min(sizeof buf, n - out.size())));
    if (got <= 0) break;
    out.insert(out.end(), buf, buf + got);
  }
  return out;
}

namespace {
test_support::SpawnOptions socat_options() {
  auto options = test_support::stopped_by_sigterm({});
  options.search_path = true;
  return options;
}
}  // namespace

SocatLink::SocatLink(const fs::path& a, const fs::path& b)
    : socat_({"socat", "pty,rawer,link=" + a.string(), "pty,rawer,link=" + b.string()},
             socat_options()) {
  ready_ = eventually([&] { return fs::exists(a) && fs::exists(b); });
}

}  // namespace unima::test
