#include "rpXDisplay.h"

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <thread>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <X11/Xlib.h>

#include <vtkRenderWindow.h>

namespace rp {
namespace {

std::mutex Mutex;
bool Checked = false, Found = false;
std::string Failure;
XDisplayInfo Info;
pid_t Server = -1;
Display* Connection = nullptr;  // the process's one connection, open until exit (see the header)

// Opens the display and keeps the connection, reading its default screen's size and depth. A
// server that is resetting (its last client just left) refuses for a few milliseconds: try again
// for up to `patience`.
bool Connect(const std::string& name, std::chrono::milliseconds patience, std::string& error) {
  const auto deadline = std::chrono::steady_clock::now() + patience;
  Display* display = XOpenDisplay(name.c_str());
  while (!display && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    display = XOpenDisplay(name.c_str());
  }
  if (!display) {
    error = "cannot open the X display '" + name + "' (tried for " + std::to_string(patience.count() / 1000) +
            " s)";
    return false;
  }
  const int screen = DefaultScreen(display);
  Info.Name = name;
  Info.Width = DisplayWidth(display, screen);
  Info.Height = DisplayHeight(display, screen);
  Info.Depth = DefaultDepth(display, screen);
  Connection = display;
  return true;
}

bool ServerRunning() {
  if (Server <= 0) return false;
  int status = 0;
  return waitpid(Server, &status, WNOHANG) == 0;
}

// Xvfb checks its termination flag just before it sleeps, so a SIGTERM can land in between and
// leave it asleep (Testing/Support/run-with-xvfb.sh): send it again every second, kill after 10 s.
void StopServer() {
  if (Server <= 0) return;
  kill(Server, SIGTERM);
  for (int tenths = 1; tenths <= 100 && ServerRunning(); ++tenths) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (tenths % 10 == 0) kill(Server, SIGTERM);
  }
  if (ServerRunning()) {
    kill(Server, SIGKILL);
    waitpid(Server, nullptr, 0);
  }
  Server = -1;
}

// Reads the display number Xvfb writes to the pipe once it accepts connections (20 s at most).
std::string ReadDisplayNumber(int fd) {
  std::string number;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < deadline) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 200) < 0 && errno != EINTR) break;
    if (!(p.revents & (POLLIN | POLLHUP))) continue;
    char c = 0;
    const ssize_t n = read(fd, &c, 1);
    if (n <= 0 || c == '\n') break;
    number += c;
  }
  return number;
}

bool StartPrivateServer(std::string& error) {
  int fds[2];
  if (pipe(fds) != 0) {
    error = std::string("cannot start Xvfb: pipe: ") + std::strerror(errno);
    return false;
  }
  const std::string fdText = std::to_string(fds[1]);
  const char* argv[] = {"Xvfb", "-displayfd", fdText.c_str(), "-screen", "0", "1920x1080x24",
                        "-nolisten", "tcp", "-noreset", nullptr};
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid == 0) {
    // The server goes with this process even if it dies without running its exit handlers.
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(126);
    close(fds[0]);
    const int null = open("/dev/null", O_RDWR);
    if (null >= 0) {
      dup2(null, STDIN_FILENO);
      dup2(null, STDOUT_FILENO);
      dup2(null, STDERR_FILENO);
    }
    execvp("Xvfb", const_cast<char* const*>(argv));
    _exit(127);
  }
  close(fds[1]);
  if (pid < 0) {
    close(fds[0]);
    error = std::string("cannot start Xvfb: fork: ") + std::strerror(errno);
    return false;
  }
  Server = pid;
  const std::string number = ReadDisplayNumber(fds[0]);
  close(fds[0]);
  if (number.empty()) {
    StopServer();
    error = "no Xvfb could be started (install the xvfb package, or run with a display)";
    return false;
  }
  std::atexit(StopServer);
  if (!Connect(":" + number, std::chrono::seconds(5), error)) {
    StopServer();
    return false;
  }
  setenv("DISPLAY", Info.Name.c_str(), 1);
  Info.Private = true;
  return true;
}

}  // namespace

bool EnsureXDisplay(std::string& error) {
  std::lock_guard<std::mutex> lock(Mutex);
  if (!Checked) {
    Checked = true;
    XInitThreads();
    const char* display = std::getenv("DISPLAY");
    std::string refused;
    if (display && *display) {
      Found = Connect(display, std::chrono::seconds(5), refused);
    }
    if (!Found) {
      // No display, or one that does not answer: draw on our own rather than not at all.
      Found = StartPrivateServer(Failure);
      if (Found) Info.Refused = refused;
      if (!Found) Failure = (refused.empty() ? "no X display ($DISPLAY is not set)" : refused) + " and " + Failure;
    }
  }
  if (!Found) error = Failure;
  return Found;
}

bool PrepareOffscreenWindow(vtkRenderWindow* window, std::string& error) {
  std::string why;
  if (!EnsureXDisplay(why)) {
    error = "no X display for offscreen pictures: " + why;
    return false;
  }
  window->SetOffScreenRendering(1);
  window->SetDisplayId(Connection);  // VTK's X window then never opens (nor closes) one itself
  return true;
}

XDisplayInfo CurrentXDisplay() {
  std::lock_guard<std::mutex> lock(Mutex);
  return Found ? Info : XDisplayInfo{};
}

}  // namespace rp
