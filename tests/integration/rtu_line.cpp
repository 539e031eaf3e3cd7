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

#include "modbus/rtu_adu.hpp"

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
  char name[256];
  if (::openpty(&master_, &slave_, name, nullptr, nullptr) != 0) throw std::runtime_error("openpty");
  // Raw from the start: a fresh terminal echoes, and would answer the test's own bytes
  // before the daemon has set it up.
  termios tio{};
  ::tcgetattr(slave_, &tio);
  ::cfmakeraw(&tio);
  ::tcsetattr(slave_, TCSANOW, &tio);
  ::fcntl(master_, F_SETFD, FD_CLOEXEC);
  ::fcntl(slave_, F_SETFD, FD_CLOEXEC);
  // Re-pointed by a rename, so the daemon never sees the link missing or half made.
  const auto tmp = fs::path(link_.string() + ".new");
  std::error_code ec;
  fs::remove(tmp, ec);
  fs::create_symlink(name, tmp);
  fs::rename(tmp, link_);
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

SocatLink::SocatLink(const fs::path& a, const fs::path& b) {
  pid_ = ::fork();
  if (pid_ < 0) throw std::runtime_error("fork");
  if (pid_ == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, STDOUT_FILENO);
    ::dup2(null, STDERR_FILENO);
    const std::string end_a = "pty,rawer,link=" + a.string();
    const std::string end_b = "pty,rawer,link=" + b.string();
    ::execlp("socat", "socat", end_a.c_str(), end_b.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ready_ = eventually([&] { return fs::exists(a) && fs::exists(b); });
}

SocatLink::~SocatLink() {
  if (pid_ > 0) {
    ::kill(pid_, SIGTERM);
    ::waitpid(pid_, nullptr, 0);
  }
}

}  // namespace unima::test
