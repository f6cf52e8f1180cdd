// termios2 lives in <asm/termbits.h>, which clashes with glibc's <termios.h>: keep it alone here.
#include <asm/termbits.h>
#include <sys/ioctl.h>

#include <cerrno>
#include <cstring>
#include <string>

namespace rp {

bool SetCustomBaudRate(int fd, int baud, std::string& error) {
  struct termios2 tio;
  if (ioctl(fd, TCGETS2, &tio) != 0) {
    error = std::string("TCGETS2 failed: ") + std::strerror(errno);
    return false;
  }
  tio.c_cflag &= ~CBAUD;
  tio.c_cflag |= BOTHER;
  tio.c_ispeed = static_cast<speed_t>(baud);
  tio.c_ospeed = static_cast<speed_t>(baud);
  if (ioctl(fd, TCSETS2, &tio) != 0) {
    error = std::string("TCSETS2 (") + std::to_string(baud) + " baud) failed: " + std::strerror(errno);
    return false;
  }
  return true;
}

}  // namespace rp
