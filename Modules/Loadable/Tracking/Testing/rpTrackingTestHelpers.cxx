#include "rpTrackingTestHelpers.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <thread>

extern char** environ;

namespace rp {
namespace test {

bool WaitFor(const std::function<bool()>& condition, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return condition();
}

int FreePort() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t len = sizeof a;
  getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  ::close(fd);
  return ntohs(a.sin_port);
}

ToolPose Newest(const ToolPoseTable& table, const std::string& name, uint64_t* count) {
  ToolPose pose;
  const int slot = table.Find(name.c_str(), name.size());
  const uint64_t n = slot >= 0 ? table.Read(slot, pose) : 0;
  if (count) *count = n;
  return pose;
}

IgtlClient::Options LoopbackClientOptions(int port) {
  IgtlClient::Options o;
  o.Host = "127.0.0.1";
  o.Port = port;
  o.ReconnectInitialSeconds = 0.05;
  o.ReconnectMaxSeconds = 0.2;
  return o;
}

void TestMatrix(double m[16], double shift) {
  const double angle = 0.7, c = std::cos(angle), s = std::sin(angle), a = 1 / std::sqrt(3.0);
  const double axis[3] = {a, a, a};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) {
      double v = (1 - c) * axis[r] * axis[k] + (r == k ? c : 0);
      if (r != k) v += ((k == (r + 1) % 3) ? -1 : 1) * s * axis[3 - r - k];  // skew part
      m[4 * r + k] = v;
    }
  m[3] = 12.5 + shift;
  m[7] = -40.25;
  m[11] = -1500.5;
  m[12] = m[13] = m[14] = 0;
  m[15] = 1;
}

bool PortListening(int port) {
  // /proc/net/tcp{,6}: "sl local_address rem_address st ...", addresses as HEXIP:HEXPORT, st 0A = LISTEN.
  char wanted[8];
  std::snprintf(wanted, sizeof wanted, ":%04X", port);
  for (const char* table : {"/proc/net/tcp", "/proc/net/tcp6"}) {
    std::ifstream f(table);
    std::string line;
    std::getline(f, line);
    while (std::getline(f, line)) {
      std::istringstream fields(line);
      std::string slot, local, remote, state;
      fields >> slot >> local >> remote >> state;
      if (state == "0A" && local.size() > 5 && local.compare(local.size() - 5, 5, wanted) == 0) return true;
    }
  }
  return false;
}

IgtlTestClient::IgtlTestClient(int port, const char* from, const char* to) {
  this->Fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in local{}, remote{};
  local.sin_family = remote.sin_family = AF_INET;
  remote.sin_port = htons(static_cast<uint16_t>(port));
  inet_pton(AF_INET, to, &remote.sin_addr);
  bool bound = true;
  if (from) bound = inet_pton(AF_INET, from, &local.sin_addr) == 1 && ::bind(this->Fd, reinterpret_cast<sockaddr*>(&local), sizeof local) == 0;
  this->IsConnected = bound && ::connect(this->Fd, reinterpret_cast<sockaddr*>(&remote), sizeof remote) == 0;
}

IgtlTestClient::~IgtlTestClient() { ::close(this->Fd); }

bool IgtlTestClient::Send(const std::vector<uint8_t>& m) {
  return ::send(this->Fd, m.data(), m.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(m.size());
}

bool IgtlTestClient::ReadExactly(uint8_t* p, size_t n, double deadline) {
  while (n > 0) {
    pollfd f{this->Fd, POLLIN, 0};
    if (::poll(&f, 1, static_cast<int>(std::max(0.0, deadline - SteadySeconds()) * 1000)) <= 0) return false;
    const ssize_t got = ::recv(this->Fd, p, n, 0);
    if (got <= 0) return false;
    p += got;
    n -= static_cast<size_t>(got);
  }
  return true;
}

bool IgtlTestClient::Next(const char* type, igtl::Header& h, std::vector<uint8_t>& body, double seconds) {
  const double deadline = SteadySeconds() + seconds;
  while (SteadySeconds() < deadline) {
    uint8_t header[igtl::HeaderSize];
    if (!this->ReadExactly(header, sizeof header, deadline) || igtl::ParseHeader(header, h, 1u << 20) != igtl::Status::Ok) return false;
    body.resize(h.BodySize);
    if (!this->ReadExactly(body.data(), body.size(), deadline)) return false;
    if (h.Is(type)) return true;
  }
  return false;
}

bool IgtlTestClient::Command(const std::string& xml, std::string& status, std::string& message) {
  std::vector<uint8_t> content(igtl::CommandHeaderSize + xml.size());
  igtl::EncodeCommand(++this->Id, "Command", xml.data(), xml.size(), content.data());
  if (!this->Send(igtl::BuildMessage(2, "COMMAND", "CMD", WallSeconds(), content.data(), content.size(), {}, this->Id))) return false;
  igtl::Header h;
  std::vector<uint8_t> body;
  igtl::Body split;
  if (!this->Next("RTS_COMMAND", h, body) || igtl::SplitBody(h, body.data(), split) != igtl::Status::Ok) return false;
  uint32_t size = 0;
  const char* s = split.Find("Status", size);
  status = s ? std::string(s, size) : "";
  const char* m = split.Find("Message", size);
  message = m ? std::string(m, size) : "";
  return true;
}

ChildProcess::~ChildProcess() { this->Kill(); }

bool ChildProcess::Start(const std::vector<std::string>& arguments, const std::string& outputFile, std::string& error) {
  this->OutputFile = outputFile;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, outputFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  std::vector<char*> argv;
  for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const int rc = posix_spawn(&this->Pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) {
    error = "cannot run " + arguments[0] + ": " + std::strerror(rc);
    this->Pid = -1;
    return false;
  }
  return true;
}

bool ChildProcess::Running() {
  if (this->Pid < 0) return false;
  int status = 0;
  const pid_t r = ::waitpid(this->Pid, &status, WNOHANG);
  if (r == this->Pid) {
    this->Status = status;
    this->Pid = -1;
    return false;
  }
  return true;
}

bool ChildProcess::WaitExit(double seconds) {
  return WaitFor([&] { return !this->Running(); }, seconds);
}

void ChildProcess::Kill() {
  if (this->Pid < 0) return;
  ::kill(this->Pid, SIGKILL);
  int status = 0;
  ::waitpid(this->Pid, &status, 0);
  this->Status = status;
  this->Pid = -1;
}

std::string ChildProcess::Output() const {
  std::ifstream f(this->OutputFile);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

std::vector<std::array<double, 16>> PrintedMatrices(const std::string& output) {
  std::vector<std::array<double, 16>> matrices;
  std::istringstream in(output);
  std::string line;
  while (std::getline(in, line)) {
    if (line != "=============") continue;
    std::array<double, 16> m{};
    int row = 0;
    for (; row < 4 && std::getline(in, line); ++row) {
      std::istringstream values(line);
      char comma;
      for (int k = 0; k < 4; ++k) {
        values >> m[4 * row + k];
        if (k < 3) values >> comma;
      }
      if (!values) break;
    }
    if (row == 4 && std::getline(in, line) && line == "=============") matrices.push_back(m);
  }
  return matrices;
}

size_t Count(const std::string& text, const std::string& needle) {
  size_t n = 0;
  for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + needle.size())) ++n;
  return n;
}

}  // namespace test
}  // namespace rp
