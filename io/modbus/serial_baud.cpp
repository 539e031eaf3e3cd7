// termios2 (BOTHER) for rates that termios has no constant for. Includes no <termios.h>:
// the two headers define the same names differently.

#include <asm/termbits.h>
#include <sys/ioctl.h>

#include <cerrno>

namespace unima::io {

int set_custom_baud(int fd, unsigned baud) {
  struct termios2 tio {};
  if (::ioctl(fd, TCGETS2, &tio) != 0) return errno;
  tio.c_cflag &= ~CBAUD;
  tio.c_cflag |= BOTHER;
  tio.c_ispeed = baud;
  tio.c_ospeed = baud;
  if (::ioctl(fd, TCSETS2, &tio) != 0) return errno;
  return 0;
}

}  // namespace unima::io
