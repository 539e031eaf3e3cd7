#include "tests/support/pseudo_terminal.hpp"

#include <fcntl.h>
#include <pty.h>
#include <termios.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace unima::test_support {

PseudoTerminal open_raw_pseudo_terminal() {
  PseudoTerminal pty;
  char name[256];
  if (::openpty(&pty.master, &pty.slave, name, nullptr, nullptr) != 0)
    throw std::runtime_error(std::string("openpty: ") + std::strerror(errno));
  pty.name = name;
  termios tio{};
  ::tcgetattr(pty.slave, &tio);
  ::cfmakeraw(&tio);
  ::tcsetattr(pty.slave, TCSANOW, &tio);
  ::fcntl(pty.master, F_SETFD, FD_CLOEXEC);
  ::fcntl(pty.slave, F_SETFD, FD_CLOEXEC);
  return pty;
}

void point_link_at(const std::filesystem::path& link, const std::string& name) {
  const auto tmp = std::filesystem::path(link.string() + ".new");
  std::error_code ec;
  std::filesystem::remove(tmp, ec);
  std::filesystem::create_symlink(name, tmp);
  std::filesystem::rename(tmp, link);
}

}  // namespace unima::test_support
