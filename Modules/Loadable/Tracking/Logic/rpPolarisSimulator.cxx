#include "rpPolarisSimulator.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "rpNdiProtocol.h"
#include "rpResources.h"
#include "rpSerialTransport.h"
#include "rpToolPose.h"

namespace rp {

std::vector<std::string> DefaultToolFiles() {
  std::vector<std::string> files;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(ResourcePath("Tools"), ec))
    if (entry.path().extension() == ".json") files.push_back(entry.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

namespace {
void PutU16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v);
  p[1] = static_cast<uint8_t>(v >> 8);
}
void PutU32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
void PutF32(uint8_t* p, double v) {
  const float f = static_cast<float>(v);
  uint32_t bits;
  std::memcpy(&bits, &f, 4);
  PutU32(p, bits);
}
// "+12345" style fixed-width signed decimal.
void PutSigned(std::string& out, double value, int digits) {
  long v = std::lround(value);
  const long limit = static_cast<long>(std::pow(10, digits)) - 1;
  if (v > limit) v = limit;
  if (v < -limit) v = -limit;
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%c%0*ld", v < 0 ? '-' : '+', digits, v < 0 ? -v : v);
  out += buffer;
}
void PutHex(std::string& out, uint32_t v, int digits) {
  char buffer[12];
  ndi::WriteHex(buffer, v, digits);
  out.append(buffer, static_cast<size_t>(digits));
}
}  // namespace

PolarisSimulator::PolarisSimulator() : PolarisSimulator(Options()) {}
PolarisSimulator::PolarisSimulator(Options options) : Opts(std::move(options)), Rng(Opts.Seed) {}
PolarisSimulator::~PolarisSimulator() { this->Stop(); }

void PolarisSimulator::AddTool(const ToolDefinition& tool, int wiredPort) {
  auto runtime = std::make_unique<ToolRuntime>();
  runtime->Definition = tool;
  runtime->WiredPort = wiredPort;
  if (runtime->Definition.Rom.empty()) runtime->Definition.Rom = rom::Build(tool.PartNumber, tool.Markers);
  std::string error;  // a ROM that does not read leaves the geometry empty: always visible
  rom::Read(runtime->Definition.Rom.data(), runtime->Definition.Rom.size(), runtime->Rom, error);
  std::lock_guard<std::mutex> lock(this->ToolsMutex);
  this->Tools.push_back(std::move(runtime));
}

int PolarisSimulator::ToolForRom(const std::vector<uint8_t>& image) {
  for (size_t t = 0; t < this->Tools.size(); ++t) {
    if (this->Tools[t]->WiredPort >= 0) continue;  // a wired tool is its port's, not a ROM's
    const auto& known = this->Tools[t]->Definition.Rom;
    if (known.size() <= image.size() && std::equal(known.begin(), known.end(), image.begin())) return static_cast<int>(t);
  }
  // A definition we were not given: a tool of its own, its geometry from the ROM, standing still
  // in the volume (a row of such tools 150 mm apart), as a camera tracks any tool it is sent.
  rom::Definition definition;
  std::string error;
  if (!rom::Read(image.data(), image.size(), definition, error)) return -1;
  auto runtime = std::make_unique<ToolRuntime>();
  ToolDefinition& tool = runtime->Definition;
  tool.PartNumber = definition.PartNumber;
  tool.Name = definition.PartNumber.empty() ? "ROM" + std::to_string(this->Tools.size() + 1) : definition.PartNumber;
  tool.Markers = definition.Markers;
  tool.Rom.assign(image.begin(), image.begin() + static_cast<long>(rom::Size));
  tool.Motion.Type = ToolTrajectory::Static;
  for (int k = 0; k < 3; ++k) tool.Motion.Center[k] = this->Opts.VolumeCenter[k];
  tool.Motion.Center[0] += 150.0 * static_cast<double>(this->Tools.size()) - 300.0;
  runtime->Rom = definition;
  std::lock_guard<std::mutex> lock(this->ToolsMutex);
  this->Tools.push_back(std::move(runtime));
  return static_cast<int>(this->Tools.size() - 1);
}

std::vector<std::string> PolarisSimulator::ToolNames() const {
  std::lock_guard<std::mutex> lock(this->ToolsMutex);
  std::vector<std::string> names;
  for (const auto& t : this->Tools) names.push_back(t->Definition.Name);
  return names;
}

std::vector<std::array<double, 3>> PolarisSimulator::ToolMarkers(const std::string& toolName) const {
  std::lock_guard<std::mutex> lock(this->ToolsMutex);
  for (const auto& t : this->Tools)
    if (t->Definition.Name == toolName) return t->Definition.Markers;
  return {};
}

double PolarisSimulator::Now() const { return SteadySeconds() - this->StartTime; }

bool PolarisSimulator::OpenPty(std::string& error) {
  int master;
  std::string slave;
  if (!OpenPseudoTerminal(master, slave, error)) return false;
  // Keep one slave descriptor open ourselves: a master without any slave reads EIO at once.
  const int keep = ::open(slave.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC | O_NONBLOCK);
  if (keep < 0) {
    error = "cannot open pty slave " + slave;
    ::close(master);
    return false;
  }
  {
    std::lock_guard<std::mutex> lock(this->PtyMutex);
    this->MasterFd = master;
    this->KeepSlaveFd = keep;
    this->Slave = slave;
  }
  if (!this->Opts.LinkPath.empty()) {
    // Re-point the link atomically so a host re-opening the path finds the new pty.
    const std::string tmp = this->Opts.LinkPath + ".tmp";
    ::unlink(tmp.c_str());
    if (::symlink(slave.c_str(), tmp.c_str()) != 0 || ::rename(tmp.c_str(), this->Opts.LinkPath.c_str()) != 0) {
      error = "cannot create link " + this->Opts.LinkPath + " -> " + slave;
      return false;
    }
  }
  return true;
}

void PolarisSimulator::ClosePty() {
  std::lock_guard<std::mutex> lock(this->PtyMutex);
  if (this->MasterFd >= 0) ::close(this->MasterFd);
  if (this->KeepSlaveFd >= 0) ::close(this->KeepSlaveFd);
  this->MasterFd = this->KeepSlaveFd = -1;
}

bool PolarisSimulator::Start(std::string& error) {
  this->Stop();
  this->StartTime = SteadySeconds();
  this->PowerOnReset();
  this->Rate = this->Opts.FrameRate;
  if (this->Tcp()) {
    if (!this->OpenListener(error)) return false;
  } else if (!this->OpenPty(error)) {
    return false;
  }
  if (!this->Tcp() && !this->Opts.LinkPath.empty()) {
    const std::string socketPath = this->Opts.LinkPath + ".break";
    ::unlink(socketPath.c_str());
    this->BreakSocketFd = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::strncpy(addr.sun_path, socketPath.c_str(), sizeof addr.sun_path - 1);
    if (this->BreakSocketFd < 0 || socketPath.size() >= sizeof addr.sun_path ||
        ::bind(this->BreakSocketFd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
      error = "cannot bind break socket " + socketPath;
      this->ClosePty();
      return false;
    }
  }
  this->Unplugged = false;
  this->Worker.Start([this] { this->Run(); });
  return true;
}

void PolarisSimulator::Stop() {
  this->Worker.Stop();
  this->ClosePty();
  if (this->ListenFd >= 0) ::close(this->ListenFd);
  this->ListenFd = -1;
  if (this->BreakSocketFd >= 0) {
    ::close(this->BreakSocketFd);
    this->BreakSocketFd = -1;
    ::unlink((this->Opts.LinkPath + ".break").c_str());
  }
  if (!this->Tcp() && !this->Opts.LinkPath.empty()) ::unlink(this->Opts.LinkPath.c_str());
}

bool PolarisSimulator::OpenListener(std::string& error) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  const int one = 1;
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);  // loopback only
  // After an Unplug the same port again, so that a driver retrying its address finds it.
  const int port = this->BoundPort > 0 ? this->BoundPort.load() : this->Opts.TcpPort;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  socklen_t length = sizeof addr;
  if (fd < 0 || ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) != 0 ||
      ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 || ::listen(fd, 4) != 0 ||
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &length) != 0) {
    error = "cannot listen on 127.0.0.1:" + std::to_string(port) + ": " + std::strerror(errno);
    if (fd >= 0) ::close(fd);
    return false;
  }
  std::lock_guard<std::mutex> lock(this->PtyMutex);
  this->ListenFd = fd;
  this->BoundPort = ntohs(addr.sin_port);
  return true;
}

void PolarisSimulator::AcceptClient() {
  const int fd = ::accept4(this->ListenFd, nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK);
  if (fd < 0) return;
  // One host at a time, as the Vega's API port: a new connection replaces the old one (a host
  // reconnecting after a network fault must not find the device taken by its own dead socket).
  std::lock_guard<std::mutex> lock(this->PtyMutex);
  if (this->MasterFd >= 0) ::close(this->MasterFd);
  this->MasterFd = fd;
  this->Input.clear();
}

std::string PolarisSimulator::SlavePath() const {
  std::lock_guard<std::mutex> lock(this->PtyMutex);
  return this->Slave;
}

std::string PolarisSimulator::PortPath() const {
  if (this->Tcp()) return "127.0.0.1:" + std::to_string(this->BoundPort.load());
  return this->Opts.LinkPath.empty() ? this->SlavePath() : this->Opts.LinkPath;
}

void PolarisSimulator::Unplug() {
  this->Unplugged = true;
  // The port disappears, as /dev/ttyUSB0 does when a USB-serial cable is pulled. A link left
  // pointing at the closed pty would name whatever pty the system hands out next under that
  // number (another process's, another simulator's): a host retrying the path would talk to it.
  if (!this->Tcp() && !this->Opts.LinkPath.empty()) ::unlink(this->Opts.LinkPath.c_str());
  // The thread stops touching the fds within one poll period; close them under the lock.
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  this->ClosePty();
  std::lock_guard<std::mutex> lock(this->PtyMutex);
  if (this->ListenFd >= 0) ::close(this->ListenFd);
  this->ListenFd = -1;
}

bool PolarisSimulator::Replug(std::string& error) {
  if (this->Tcp() ? !this->OpenListener(error) : !this->OpenPty(error)) return false;
  this->BreakPending = false;
  this->Unplugged = false;  // the thread resets the device state when it sees the new pty
  return true;
}

void PolarisSimulator::SetOccluded(const std::string& toolName, bool occluded) {
  std::lock_guard<std::mutex> lock(this->ToolsMutex);
  for (auto& t : this->Tools)
    if (t->Definition.Name == toolName) t->Occluded = occluded;
}

void PolarisSimulator::SetOutOfVolume(const std::string& toolName, bool outOfVolume) {
  std::lock_guard<std::mutex> lock(this->ToolsMutex);
  for (auto& t : this->Tools)
    if (t->Definition.Name == toolName) t->OutOfVolume = outOfVolume;
}

PolarisSimulator::Counters PolarisSimulator::GetCounters() const {
  std::lock_guard<std::mutex> lock(this->CountersMutex);
  return this->Count;
}

bool PolarisSimulator::TruePose(const std::string& toolName, double t, double m[16]) const {
  std::lock_guard<std::mutex> lock(this->ToolsMutex);
  for (auto& tool : this->Tools) {
    if (tool->Definition.Name == toolName) {
      EvaluateTrajectory(tool->Definition, t, m);
      return true;
    }
  }
  return false;
}

void PolarisSimulator::LoadPluggedSrom(Handle& h) const {
  const auto& srom = this->Tools[static_cast<size_t>(h.WiredTool)]->Definition.Rom;
  std::fill(h.Rom.begin(), h.Rom.end(), uint8_t{0});
  std::copy(srom.begin(), srom.begin() + static_cast<long>(std::min(srom.size(), h.Rom.size())), h.Rom.begin());
}

void PolarisSimulator::PowerOnReset() {
  this->Handles.clear();
  {  // each occupied wired port has a handle from power-on (01, 02, ...), its SROM the tool's
    std::lock_guard<std::mutex> lock(this->ToolsMutex);
    for (size_t t = 0; t < this->Tools.size(); ++t) {
      if (this->Tools[t]->WiredPort < 0) continue;
      Handle h;
      h.Number = static_cast<int>(this->Handles.size()) + 1;
      h.WiredTool = static_cast<int>(t);
      this->LoadPluggedSrom(h);
      this->Handles.push_back(h);
    }
  }
  this->Input.clear();
  this->Initialized = false;
  this->Tracking = false;
  this->Baud = 9600;
  this->Rate = this->Opts.FrameRate;
  std::lock_guard<std::mutex> lock(this->CountersMutex);
  this->Count.Baud = 9600;
  this->Count.Tracking = false;
  this->Count.LoadedTools = 0;
}

void PolarisSimulator::Run() {
  bool wasUnplugged = false;
  char buffer[4096];
  while (!this->Worker.StopRequested()) {
    if (this->Unplugged) {
      wasUnplugged = true;
      this->Worker.Sleep(0.005);
      continue;
    }
    if (wasUnplugged) {  // a replugged device starts from power-on
      wasUnplugged = false;
      this->PowerOnReset();
    }
    if (this->BreakPending.exchange(false)) {
      {
        std::lock_guard<std::mutex> lock(this->CountersMutex);
        ++this->Count.Breaks;
      }
      if (this->Opts.AcceptBreak) {
        this->PowerOnReset();
        this->Reply("RESET");
      }
    }
    int master, listener;
    {
      std::lock_guard<std::mutex> lock(this->PtyMutex);
      master = this->MasterFd;
      listener = this->ListenFd;
    }
    if (master < 0 && listener < 0) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      continue;
    }
    pollfd fds[3] = {{master, POLLIN, 0}, {this->BreakSocketFd, POLLIN, 0}, {listener, POLLIN, 0}};
    const int ready = ::poll(fds, 3, 5);  // negative descriptors are ignored
    if (ready <= 0 || this->Unplugged) continue;
    if (fds[2].revents & POLLIN) this->AcceptClient();
    if (this->BreakSocketFd >= 0 && (fds[1].revents & POLLIN)) {
      char message[64];
      while (::recv(this->BreakSocketFd, message, sizeof message, 0) > 0) this->BreakPending = true;
    }
    if (fds[0].revents & (POLLIN | POLLHUP | POLLERR)) {
      const ssize_t n = ::read(master, buffer, sizeof buffer);
      if (n > 0) this->Input.append(buffer, static_cast<size_t>(n));
      if (this->Tcp() && (n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR))) {
        std::lock_guard<std::mutex> lock(this->PtyMutex);  // the host hung up: wait for the next one
        if (this->MasterFd == master) {
          ::close(master);
          this->MasterFd = -1;
        }
        this->Input.clear();
        continue;
      }
      if (this->Input.size() > 65536) this->Input.clear();  // garbage: nobody sends this much
      size_t cr;
      while ((cr = this->Input.find('\r')) != std::string::npos) {
        const std::string line = this->Input.substr(0, cr);
        this->Input.erase(0, cr + 1);
        this->HandleCommand(line.data(), line.size());
      }
    }
  }
}

void PolarisSimulator::SendRaw(uint8_t* data, size_t length, bool ascii) {
  if (this->Drops > 0) {
    --this->Drops;
    return;
  }
  if (this->CrcFaults > 0) {
    --this->CrcFaults;
    // Corrupt the checksum itself: the payload stays plausible, only the CRC can tell.
    if (ascii) data[length - 2] = data[length - 2] == '0' ? '1' : '0';
    else data[length - 1] ^= 0x5A;
  }
  const int delay = this->DelayMs;
  if (delay > 0) std::this_thread::sleep_for(std::chrono::milliseconds(delay));
  std::lock_guard<std::mutex> lock(this->PtyMutex);
  if (this->MasterFd < 0 || this->Unplugged) return;
  size_t done = 0;
  while (done < length) {
    const ssize_t n = this->Tcp() ? ::send(this->MasterFd, data + done, length - done, MSG_NOSIGNAL)
                                  : ::write(this->MasterFd, data + done, length - done);
    if (n <= 0) return;  // host not reading: a real device drops it too
    done += static_cast<size_t>(n);
  }
}

void PolarisSimulator::Reply(const char* payload) {
  std::string text(payload);
  char crc[4];
  ndi::WriteHex(crc, ndi::Crc16(text.data(), text.size()), 4);
  text.append(crc, 4);
  text += '\r';
  this->SendRaw(reinterpret_cast<uint8_t*>(&text[0]), text.size(), true);
}

void PolarisSimulator::ReplyError(int code) {
  char text[8] = "ERROR";
  ndi::WriteHex(text + 5, static_cast<uint32_t>(code), 2);
  text[7] = '\0';
  this->Reply(text);
}

void PolarisSimulator::ReplyBinary(const uint8_t* body, size_t length) {
  std::vector<uint8_t> frame(length + 8);
  frame[0] = 0xC4;
  frame[1] = 0xA5;
  PutU16(&frame[2], static_cast<uint16_t>(length));
  PutU16(&frame[4], ndi::Crc16(frame.data(), 4));
  std::memcpy(&frame[6], body, length);
  PutU16(&frame[6 + length], ndi::Crc16(body, length));
  this->SendRaw(frame.data(), frame.size(), false);
}

PolarisSimulator::Handle* PolarisSimulator::FindHandle(const char* hex) {
  uint32_t number;
  if (!ndi::ParseHex(hex, 2, number)) return nullptr;
  for (auto& h : this->Handles)
    if (h.Number == static_cast<int>(number)) return &h;
  return nullptr;
}

uint32_t PolarisSimulator::CurrentFrame() const {
  return static_cast<uint32_t>(std::floor((this->Now() - this->TrackingStart) * this->Rate)) + 1;
}

// The NDI commands the simulator answers, one handler each (as PLUS's and NDI's simulators do); a
// command not listed answers ERROR01, and any command but these first five needs INIT (ERROR10).
struct PolarisSimulator::CommandEntry {
  const char* Name;
  bool NeedsInit;
  CommandHandler Run;
};

const PolarisSimulator::CommandEntry PolarisSimulator::CommandTable[] = {
    {"RESET", false, &PolarisSimulator::OnReset},     {"INIT", false, &PolarisSimulator::OnInit},
    {"GETINFO", false, &PolarisSimulator::OnGetInfo}, {"VER", false, &PolarisSimulator::OnVersion},
    {"COMM", false, &PolarisSimulator::OnComm},       {"IRATE", true, &PolarisSimulator::OnIrate},
    {"VSEL", true, &PolarisSimulator::OnAcknowledge}, {"BEEP", true, &PolarisSimulator::OnAcknowledge},
    {"LED", true, &PolarisSimulator::OnAcknowledge},  {"PHSR", true, &PolarisSimulator::OnPhsr},
    {"PHRQ", true, &PolarisSimulator::OnPhrq},        {"PHF", true, &PolarisSimulator::OnPhf},
    {"PVWR", true, &PolarisSimulator::OnPvwr},        {"PINIT", true, &PolarisSimulator::OnPinit},
    {"PHINF", true, &PolarisSimulator::OnPhinf},      {"PENA", true, &PolarisSimulator::OnPena},
    {"PDIS", true, &PolarisSimulator::OnPdis},        {"TSTART", true, &PolarisSimulator::OnTstart},
    {"TSTOP", true, &PolarisSimulator::OnTstop},      {"TX", true, &PolarisSimulator::OnTracking},
    {"BX", true, &PolarisSimulator::OnTracking},
};

void PolarisSimulator::HandleCommand(const char* line, size_t length) {
  {
    std::lock_guard<std::mutex> lock(this->CountersMutex);
    ++this->Count.Commands;
  }
  std::string name, args;
  if (!this->SplitCommand(std::string(line, length), name, args)) return;
  const CommandEntry* entry = nullptr;
  for (const CommandEntry& e : CommandTable)
    if (name == e.Name) entry = &e;
  if ((!entry || entry->NeedsInit) && !this->Initialized) return this->ReplyError(0x10);
  if (!entry) return this->ReplyError(0x01);
  (this->*entry->Run)(name, args);
}

bool PolarisSimulator::SplitCommand(std::string text, std::string& name, std::string& args) {
  // Strip stray line feeds some hosts send.
  while (!text.empty() && (text.front() == '\n')) text.erase(0, 1);
  const size_t separator = text.find_first_of(": ");
  name = text.substr(0, separator);
  if (separator != std::string::npos && text[separator] == ':') {
    // "NAME:args" + CRC: the device checks the CRC only after a colon.
    if (text.size() < separator + 5) {
      this->ReplyError(0x04);
      return false;
    }
    const std::string crcText = text.substr(text.size() - 4);
    uint32_t crc;
    if (!ndi::ParseHex(crcText.c_str(), 4, crc) || ndi::Crc16(text.data(), text.size() - 4) != crc) {
      {
        std::lock_guard<std::mutex> lock(this->CountersMutex);
        ++this->Count.CrcErrorsSeen;
      }
      this->ReplyError(0x04);
      return false;
    }
    args = text.substr(separator + 1, text.size() - 4 - separator - 1);
  } else if (separator != std::string::npos) {
    args = text.substr(separator + 1);
  }
  return true;
}

void PolarisSimulator::OnReset(const std::string&, const std::string&) {
  this->PowerOnReset();
  {
    std::lock_guard<std::mutex> lock(this->CountersMutex);
    ++this->Count.Resets;
  }
  this->Reply("RESET");
}

void PolarisSimulator::OnInit(const std::string&, const std::string&) {
  this->Initialized = true;
  this->Reply("OKAY");
}

void PolarisSimulator::OnGetInfo(const std::string&, const std::string&) {
  this->ReplyError(0x01);  // Spectra/Vicra: old API
}

void PolarisSimulator::OnVersion(const std::string&, const std::string&) {
  this->Reply("Polaris Spectra (RoboPlan simulator)\nFreeze Tag: 1.0\nCombined Firmware Revision: 006");
}

void PolarisSimulator::OnComm(const std::string&, const std::string& args) {
  static const int kBauds[] = {9600, 14400, 19200, 38400, 57600, 115200, 921600, 1228739};
  if (args.size() != 5) return this->ReplyError(0x07);
  const char code = args[0];
  int baud = 0;
  if (code >= '0' && code <= '7') baud = kBauds[code - '0'];
  else if (code == 'A') baud = 230400;
  else return this->ReplyError(0x06);
  this->Baud = baud;  // a pty has no baud rate: only the state changes
  {
    std::lock_guard<std::mutex> lock(this->CountersMutex);
    this->Count.Baud = baud;
  }
  this->Reply("OKAY");
}

void PolarisSimulator::OnIrate(const std::string&, const std::string& args) {
  if (args == "0") this->Rate = 20;
  else if (args == "1") this->Rate = 30;
  else if (args == "2") this->Rate = 60;
  else return this->ReplyError(0x23);
  this->Reply("OKAY");
}

void PolarisSimulator::OnAcknowledge(const std::string& name, const std::string&) {
  this->Reply(name == "BEEP" ? "1" : "OKAY");  // VSEL, BEEP, LED
}

void PolarisSimulator::OnPhsr(const std::string&, const std::string& args) {
  std::string out;
  std::vector<const Handle*> listed;
  for (const auto& h : this->Handles) {
    if (args == "01" && h.WiredTool >= 0) continue;  // a plugged-in wired tool needs no freeing
    if (args == "02" && (h.Initialized)) continue;
    if (args == "03" && (!h.Initialized || h.Enabled)) continue;
    if (args == "04" && !h.Enabled) continue;
    listed.push_back(&h);
  }
  PutHex(out, static_cast<uint32_t>(listed.size()), 2);
  for (const Handle* h : listed) {
    PutHex(out, static_cast<uint32_t>(h->Number), 2);
    PutHex(out, (h->Initialized ? 0x10u : 0u) | (h->Enabled ? 0x20u : 0u) | 0x01u, 3);
  }
  this->Reply(out.c_str());
}

void PolarisSimulator::OnPhrq(const std::string&, const std::string&) {
  if (this->Handles.size() >= 12) return this->ReplyError(0x2D);
  int number = 0x0A;
  for (const auto& h : this->Handles) number = std::max(number, h.Number + 1);
  Handle h;
  h.Number = number;
  this->Handles.push_back(h);
  std::string out;
  PutHex(out, static_cast<uint32_t>(number), 2);
  this->Reply(out.c_str());
}

PolarisSimulator::Handle* PolarisSimulator::CommandHandle(const std::string& args) {
  if (args.size() < 2) {
    this->ReplyError(0x07);
    return nullptr;
  }
  Handle* h = this->FindHandle(args.c_str());
  if (!h) this->ReplyError(0x2B);
  return h;
}

void PolarisSimulator::OnPhf(const std::string&, const std::string& args) {
  Handle* h = this->CommandHandle(args);
  if (!h) return;
  if (h->WiredTool >= 0) {  // the tool stays in its port: its handle back as at power-on
    this->LoadPluggedSrom(*h);
    h->Initialized = h->Enabled = false;
    h->Tool = -1;
    h->ChunksWritten = 0;
  } else {
    this->Handles.erase(this->Handles.begin() + (h - this->Handles.data()));
  }
  this->Reply("OKAY");
}

void PolarisSimulator::OnPvwr(const std::string&, const std::string& args) {
  Handle* h = this->CommandHandle(args);
  if (!h) return;
  uint32_t address;
  if (args.size() != 2 + 4 + 128 || !ndi::ParseHex(args.c_str() + 2, 4, address)) return this->ReplyError(0x07);
  if (address % 64 != 0 || address > 0x3C0) return this->ReplyError(0x23);
  for (int i = 0; i < 64; ++i) {
    uint32_t byte;
    if (!ndi::ParseHex(args.c_str() + 6 + 2 * i, 2, byte)) return this->ReplyError(0x01);
    h->Rom[address + static_cast<uint32_t>(i)] = static_cast<uint8_t>(byte);
  }
  h->ChunksWritten = static_cast<uint16_t>(h->ChunksWritten | (1u << (address / 64)));
  this->Reply("OKAY");
}

void PolarisSimulator::OnPinit(const std::string&, const std::string& args) {
  Handle* h = this->CommandHandle(args);
  if (!h) return;
  std::string error;
  if (!rom::Validate(h->Rom, error)) return this->ReplyError(0x40);
  const auto sameAsPlugged = [&] {
    const auto& srom = this->Tools[static_cast<size_t>(h->WiredTool)]->Definition.Rom;
    return srom.size() <= h->Rom.size() && std::equal(srom.begin(), srom.end(), h->Rom.begin());
  };
  // A wired port tracks its own tool unless a virtual SROM of another definition was written over it.
  h->Tool = h->WiredTool >= 0 && sameAsPlugged() ? h->WiredTool : this->ToolForRom(h->Rom);
  h->Initialized = true;
  {
    std::lock_guard<std::mutex> lock(this->CountersMutex);
    ++this->Count.LoadedTools;
  }
  this->Reply("OKAY");
}

void PolarisSimulator::OnPhinf(const std::string&, const std::string& args) {
  const Handle* h = this->CommandHandle(args);
  if (!h) return;
  // The reply option: basic information (0001) and the port location (0020) are simulated; the
  // other fields (testing, part number, accessories, marker type, GPIO) are not.
  uint32_t option = 0x0001;
  if (args.size() != 2 && (args.size() != 6 || !ndi::ParseHex(args.c_str() + 2, 4, option))) return this->ReplyError(0x07);
  if ((option & ~0x0021u) != 0) return this->ReplyError(0x07);
  std::string out;
  if (option & 0x0001) {
    const int tool = h->Tool >= 0 ? h->Tool : h->WiredTool;
    out += h->WiredTool >= 0 ? "01000000" : "0A000000";  // tool type: reference/pointer (wired), passive
    std::string part = tool >= 0 ? this->Tools[static_cast<size_t>(tool)]->Definition.PartNumber : "UNKNOWN";
    part.resize(12, ' ');
    out += part;
    out += "000";
    out += "00000001";
    PutHex(out, (h->Initialized ? 0x10u : 0u) | (h->Enabled ? 0x20u : 0u) | 0x01u, 2);
  }
  if (option & 0x0020) {
    out += "00000000";  // device number
    out += '0';         // Polaris
    if (h->WiredTool >= 0) {
      const int port = this->Tools[static_cast<size_t>(h->WiredTool)]->WiredPort;
      char digits[8];
      std::snprintf(digits, sizeof digits, "0%02d", port % 100 + 1);
      out += digits;
      PutHex(out, static_cast<uint32_t>(port / 100), 2);
    } else {
      out += '1';                                    // wireless
      out += "0";
      out += static_cast<char>('A' + std::min(h->Number - 0x0A, 8));  // "0A".."0I"
      out += "00";
    }
  }
  this->Reply(out.c_str());
}

void PolarisSimulator::OnPena(const std::string&, const std::string& args) {
  Handle* h = this->CommandHandle(args);
  if (!h) return;
  if (!h->Initialized) return this->ReplyError(0x0E);
  h->Enabled = true;
  this->Reply("OKAY");
}

void PolarisSimulator::OnPdis(const std::string&, const std::string& args) {
  Handle* h = this->CommandHandle(args);
  if (!h) return;
  h->Enabled = false;
  this->Reply("OKAY");
}

void PolarisSimulator::OnTstart(const std::string&, const std::string&) {
  this->Tracking = true;
  this->TrackingStart = this->Now();
  {
    std::lock_guard<std::mutex> lock(this->CountersMutex);
    this->Count.Tracking = true;
  }
  this->Reply("OKAY");
}

void PolarisSimulator::OnTstop(const std::string&, const std::string&) {
  this->Tracking = false;
  {
    std::lock_guard<std::mutex> lock(this->CountersMutex);
    this->Count.Tracking = false;
  }
  this->Reply("OKAY");
}

void PolarisSimulator::OnTracking(const std::string& name, const std::string&) {
  if (!this->Tracking) return this->ReplyError(0x0C);
  {
    std::lock_guard<std::mutex> lock(this->CountersMutex);
    ++this->Count.TrackingReplies;
  }
  this->BuildTracking(name == "BX");  // TX or BX
}

bool PolarisSimulator::MarkersVisible(const ToolRuntime& tool, const double m[16]) {
  const rom::Definition& g = tool.Rom;
  if (g.Markers.empty()) return true;
  const double cosMax = std::cos(std::min(180, std::max(0, g.MaxMarkerAngleDeg)) * M_PI / 180.0);
  int visible = 0;
  for (size_t i = 0; i < g.Markers.size(); ++i) {
    const auto& p = g.Markers[i];
    const auto& nn = i < g.Normals.size() ? g.Normals[i] : rom::Vec3{0, 0, 0};
    double world[3], normal[3], distance = 0, length = 0;
    for (int r = 0; r < 3; ++r) {
      world[r] = m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3];
      normal[r] = m[4 * r] * nn[0] + m[4 * r + 1] * nn[1] + m[4 * r + 2] * nn[2];
      distance += world[r] * world[r];
      length += normal[r] * normal[r];
    }
    if (length < 1e-12) {  // no normal given: seen from everywhere
      ++visible;
      continue;
    }
    // Towards the camera (the tracker origin) is -world.
    const double facing = -(normal[0] * world[0] + normal[1] * world[1] + normal[2] * world[2]) / std::sqrt(distance * length);
    if (facing >= cosMax) ++visible;
  }
  return visible >= std::max(1, g.MinimumMarkers);
}

void PolarisSimulator::BuildTracking(bool binary) {
  const uint32_t frame = this->CurrentFrame();
  const double t = (frame - 1) / this->Rate + this->TrackingStart;
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::string text;
  uint8_t body[2048];
  size_t n = 0;
  int count = 0;
  for (const auto& h : this->Handles)
    if (h.Initialized) ++count;
  PutHex(text, static_cast<uint32_t>(count), 2);
  body[n++] = static_cast<uint8_t>(count);
  for (auto& h : this->Handles) {
    if (!h.Initialized) continue;
    PutHex(text, static_cast<uint32_t>(h.Number), 2);
    body[n++] = static_cast<uint8_t>(h.Number);
    if (!h.Enabled) {
      text += "DISABLED\n";
      body[n++] = 0x04;
      continue;
    }
    uint32_t port = ndi::PortOccupied | ndi::PortInitialized | ndi::PortEnabled;
    const ToolRuntime* tool = h.Tool >= 0 ? this->Tools[static_cast<size_t>(h.Tool)].get() : nullptr;
    double m[16];
    if (tool) EvaluateTrajectory(tool->Definition, t, m);
    if (!tool || tool->Occluded || (this->Opts.MarkerVisibility && !MarkersVisible(*tool, m))) {
      text += "MISSING";
      PutHex(text, port, 8);
      PutHex(text, frame, 8);
      text += '\n';
      body[n++] = 0x02;
      PutU32(body + n, port);
      PutU32(body + n + 4, frame);
      n += 8;
      continue;
    }
    ToolPose pose;
    pose.FromMatrix(m);
    const double sigmaT = this->Opts.NoiseMm, sigmaR = this->Opts.NoiseDeg * M_PI / 180.0;
    if (sigmaT > 0)
      for (double& v : pose.Translation) v += sigmaT * gauss(this->Rng);
    if (sigmaR > 0) {
      for (int k = 1; k < 4; ++k) pose.Quaternion[k] += 0.5 * sigmaR * gauss(this->Rng);
      double norm = 0;
      for (double q : pose.Quaternion) norm += q * q;
      for (double& q : pose.Quaternion) q /= std::sqrt(norm);
    }
    if (pose.Quaternion[0] < 0)
      for (double& q : pose.Quaternion) q = -q;
    double d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += std::pow(pose.Translation[k] - this->Opts.VolumeCenter[k], 2);
    if (tool->OutOfVolume || std::sqrt(d2) > this->Opts.VolumeRadius) port |= ndi::PortOutOfVolume;
    const double error = 0.12 + 0.02 * std::abs(gauss(this->Rng));
    for (double q : pose.Quaternion) PutSigned(text, q * 1e4, 5);
    for (double v : pose.Translation) PutSigned(text, v * 100, 6);
    PutSigned(text, error * 1e4, 5);
    PutHex(text, port, 8);
    PutHex(text, frame, 8);
    text += '\n';
    body[n++] = 0x01;
    for (double q : pose.Quaternion) {
      PutF32(body + n, q);
      n += 4;
    }
    for (double v : pose.Translation) {
      PutF32(body + n, v);
      n += 4;
    }
    PutF32(body + n, error);
    n += 4;
    PutU32(body + n, port);
    PutU32(body + n + 4, frame);
    n += 8;
  }
  PutHex(text, 0, 4);
  PutU16(body + n, 0);
  n += 2;
  if (binary) this->ReplyBinary(body, n);
  else this->Reply(text.c_str());
}

}  // namespace rp
