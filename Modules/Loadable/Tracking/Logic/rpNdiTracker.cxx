#include "rpNdiTracker.h"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "rpSerialTransport.h"
#include "rpTcpTransport.h"
#include "rpToolDefinition.h"
#include "rpTransformNames.h"

namespace rp {

const char* NdiTracker::StateName(State state) {
  switch (state) {
    case State::Stopped: return "stopped";
    case State::Connecting: return "connecting";
    case State::Configuring: return "configuring";
    case State::Tracking: return "tracking";
    case State::Disconnected: return "disconnected";
  }
  return "unknown";
}

NdiTracker::NdiTracker(Options options) : Opts(std::move(options)) {
  // Slots are registered before the I/O thread exists: names are fixed for the driver's life.
  for (const Tool& tool : this->Opts.Tools) this->Table.FindOrAdd(ToolToTrackerName(tool.Name).c_str());
  std::fill(std::begin(this->HandleSlot), std::end(this->HandleSlot), -1);
}

NdiTracker::~NdiTracker() { this->Stop(); }

namespace {
// Tools and rate options shared by the serial and the TCP source.
NdiTracker::Options OptionsFrom(const PoseSourceConfig& config) {
  NdiTracker::Options o;
  o.Port = config.Address;
  for (const std::string& file : config.ToolFiles) {
    const ToolDefinition tool = ReadToolFile(file);  // throws std::runtime_error naming the file
    o.Tools.push_back({tool.Name, tool.Rom});
  }
  // Wired tools, "NAME=PORT,...", PORT numbered as PLUS's PortName (channel * 100 + port - 1).
  std::stringstream wired(config.Option("wired"));
  for (std::string item; std::getline(wired, item, ',');) {
    const size_t equals = item.find('=');
    int port = -1;
    if (equals == 0 || equals == std::string::npos || !ndi::ParseWiredPort(item.substr(equals + 1), port))
      throw std::invalid_argument("wired tool '" + item + "': give NAME=PORT, PORT 0 for port 1 (as PLUS's PortName)");
    o.Tools.push_back({item.substr(0, equals), {}, port});
  }
  if (o.Tools.empty()) throw std::invalid_argument("give at least one tool definition (.rom or .json) or wired tool");
  const double rate = config.Number("rate", 60);
  if (rate != 20 && rate != 30 && rate != 60) throw std::invalid_argument("rate must be 20, 30 or 60 (Hz)");
  o.PollHz = rate;
  o.RateCode = rate == 20 ? 0 : rate == 30 ? 1 : 2;
  const std::string text = config.Option("text", "0");
  o.Binary = !(text == "1" || text == "true" || text == "yes");
  return o;
}
}  // namespace

std::unique_ptr<PoseSource> NdiTracker::Create(const PoseSourceConfig& config) {
  if (config.Address.empty()) throw std::invalid_argument("give the serial port (e.g. /dev/ttyUSB0)");
  return std::make_unique<NdiTracker>(OptionsFrom(config));
}

std::unique_ptr<PoseSource> NdiTracker::CreateTcp(const PoseSourceConfig& config) {
  std::string host, error;
  int port;
  if (!ParseNdiTcpAddress(config.Address, host, port, error)) throw std::invalid_argument(error);
  Options o = OptionsFrom(config);
  o.Tcp = true;
  return std::make_unique<NdiTracker>(o);
}

std::unique_ptr<NdiTransport> NdiTracker::MakeTransport() const {
  if (this->Opts.TransportFactory) return this->Opts.TransportFactory();
  if (!this->Opts.Tcp) return MakeSerialTransport(this->Opts.Port);
  std::string host, error;
  int port = NdiTcpDefaultPort;
  ParseNdiTcpAddress(this->Opts.Port, host, port, error);  // checked by CreateTcp; a bad one fails to connect
  return std::make_unique<TcpTransport>(host, port);
}


bool NdiTracker::Start(std::string&) {
  this->Worker.Start([this] { this->Run(); });
  return true;
}

void NdiTracker::Stop() { this->Worker.Stop(); }

std::string NdiTracker::StatusText() const {
  const std::string error = this->LastError();
  return std::string(StateName(this->GetState())) + (error.empty() ? "" : ": " + error);
}

nlohmann::json NdiTracker::StatisticsJson() const {
  const auto s = this->GetStatistics();
  return {{"state", StateName(this->GetState())}, {"port", this->Opts.Port}, {"link", this->Opts.Tcp ? "tcp" : "serial"},
          {"firmware", this->FirmwareVersion()},
          {"baud", this->NegotiatedBaud()}, {"frames", s.Frames}, {"crcErrors", s.CrcErrors}, {"timeouts", s.Timeouts},
          {"frameGaps", s.FrameGaps}, {"deviceErrors", s.DeviceErrors}, {"malformedReplies", s.MalformedReplies},
          {"lateReplies", s.LateReplies}, {"connections", s.Connections}, {"resets", s.Resets},
          {"threadCpuSeconds", s.ThreadCpuSeconds}, {"lastError", this->LastError()}};
}

NdiTracker::Statistics NdiTracker::GetStatistics() const {
  Statistics s;
  s.Frames = this->Frames;
  s.CrcErrors = this->CrcErrors;
  s.Timeouts = this->Timeouts;
  s.FrameGaps = this->FrameGaps;
  s.DeviceErrors = this->DeviceErrors;
  s.MalformedReplies = this->Malformed;
  s.Connections = this->Connections;
  s.Resets = this->Resets;
  s.LateReplies = this->LateReplies;
  s.ThreadCpuSeconds = this->CpuSeconds;
  return s;
}

std::string NdiTracker::FirmwareVersion() const {
  std::lock_guard<std::mutex> lock(this->VersionMutex);
  return this->Version;
}

void NdiTracker::UpdateCpu() {
  timespec ts;
  if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) == 0) this->CpuSeconds = ts.tv_sec + 1e-9 * ts.tv_nsec;
}

void NdiTracker::Run() {
  Backoff backoff(this->Opts.ReconnectInitialSeconds, this->Opts.ReconnectMaxSeconds);
  while (!this->Stopping()) {
    this->SetState(State::Connecting);
    bool ok = this->Connect();
    if (ok) {
      this->SetState(State::Configuring);
      ok = this->Configure();
    }
    if (ok) {
      ++this->Connections;
      backoff.Reset();
      this->SetState(State::Tracking);
      this->TrackLoop();
      if (this->Stopping()) {
        this->Shutdown();
        break;
      }
    }
    if (this->Transport) this->Transport->Close();
    if (this->Stopping()) break;
    this->SetState(State::Disconnected);
    this->Ready.Notify();  // the main thread shows the change of state
    this->Worker.Sleep(backoff.Next());  // never a busy loop: back off up to ReconnectMaxSeconds
  }
  if (this->Transport) this->Transport->Close();
  this->UpdateCpu();
  this->SetState(State::Stopped);
}

int NdiTracker::ReadFrame(int timeoutMs) {
  // Drop the frame handed out last time.
  if (this->FrameLength > 0) {
    std::memmove(this->Rx, this->Rx + this->FrameLength, this->RxLength - this->FrameLength);
    this->RxLength -= this->FrameLength;
    this->FrameLength = 0;
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeoutMs);
  bool triedRead = false;
  for (;;) {
    size_t length = 0;
    const ndi::ParseResult r = ndi::FindFrame(this->Rx, this->RxLength, length);
    if (r.Ok()) {
      this->FrameLength = length;
      return 0;
    }
    if (r.Code != ndi::ParseCode::Incomplete || this->RxLength == sizeof this->Rx) {
      // A binary header that cannot be right, or garbage: resynchronise one byte at a time.
      const size_t drop = r.Code == ndi::ParseCode::Oversized && this->Rx[0] != 0xC4 ? this->RxLength : 1;
      std::memmove(this->Rx, this->Rx + drop, this->RxLength - drop);
      this->RxLength -= drop;
      ++this->Malformed;
      continue;
    }
    auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0) {
      if (triedRead) return 1;
      left = 0;  // still look once at what is already there
    }
    triedRead = true;
    const long n = this->Transport->Read(this->Rx + this->RxLength, sizeof this->Rx - this->RxLength, static_cast<int>(left));
    if (n < 0) return -1;
    this->RxLength += static_cast<size_t>(n);
  }
}

ndi::ParseResult NdiTracker::Command(const char* name, const char* args, int timeoutMs, int retries) {
  char command[512];
  const size_t length = ndi::FormatCommand(command, sizeof command, name, args, args != nullptr);
  ndi::ParseResult result;
  result.Code = ndi::ParseCode::Incomplete;
  for (int attempt = 0; attempt <= retries && !this->Stopping(); ++attempt) {
    if (!this->Transport->Write(command, length)) {
      this->Fail(std::string(name) + ": " + this->Transport->LastError());
      result.Code = ndi::ParseCode::Truncated;
      return result;
    }
    const int read = this->ReadFrame(timeoutMs);
    if (read < 0) {
      this->Fail(std::string(name) + ": " + this->Transport->LastError());
      result.Code = ndi::ParseCode::Truncated;
      return result;
    }
    if (read == 1) {
      ++this->Timeouts;
      this->RxLength = 0;  // a late partial reply must not prefix the next one
      result.Code = ndi::ParseCode::Incomplete;
      continue;
    }
    result = ndi::CheckAsciiReply(this->Rx, this->FrameLength, this->Payload, this->PayloadLength);
    if (result.Code == ndi::ParseCode::BadCrc) {
      ++this->CrcErrors;
      continue;
    }
    if (result.Code == ndi::ParseCode::DeviceError) ++this->DeviceErrors;
    return result;
  }
  return result;
}

namespace {
std::string Describe(const char* command, const ndi::ParseResult& r) {
  std::string text = std::string(command) + " failed: ";
  if (r.Code == ndi::ParseCode::DeviceError) {
    char code[3];
    ndi::WriteHex(code, static_cast<uint32_t>(r.DeviceError), 2);
    return text + "ERROR" + std::string(code, 2) + " (" + ndi::ErrorCodeText(r.DeviceError) + ")";
  }
  if (r.Code == ndi::ParseCode::Incomplete) return text + "no reply (timeout)";
  return text + ndi::ParseCodeName(r.Code);
}
}  // namespace

bool NdiTracker::Reset() {
  ++this->Resets;
  this->Transport->SetBaudRate(9600);
  this->Baud = 9600;
  this->Transport->Flush();
  this->RxLength = this->FrameLength = 0;
  if (this->Transport->SendBreak(300)) {
    if (this->ReadFrame(this->Opts.CommandTimeoutMs) == 0 &&
        ndi::CheckAsciiReply(this->Rx, this->FrameLength, this->Payload, this->PayloadLength).Ok() &&
        this->PayloadLength == 5 && std::memcmp(this->Payload, "RESET", 5) == 0)
      return true;
  }
  // No break on this link (or no answer to it): the plain RESET command.
  this->RxLength = this->FrameLength = 0;
  const ndi::ParseResult r = this->Command("RESET", nullptr, this->Opts.CommandTimeoutMs, 1);
  if (r.Ok() && this->PayloadLength == 5 && std::memcmp(this->Payload, "RESET", 5) == 0) return true;
  this->Fail(Describe("RESET", r));
  return false;
}

bool NdiTracker::Connect() {
  this->Transport = this->MakeTransport();
  this->RxLength = this->FrameLength = 0;
  if (!this->Transport->Open()) {
    this->Fail(this->Transport->LastError());
    return false;
  }
  this->Baud = 9600;
  // A serial probe is short (a device at another baud rate never answers); a Vega's first INIT
  // over TCP can take seconds (PLUS gives it 5).
  const int probeMs = this->Transport->HasBaudRate() ? this->Opts.ProbeTimeoutMs : this->Opts.CommandTimeoutMs;
  ndi::ParseResult r = this->Command("INIT", "", probeMs, 0);
  if (r.Ok()) return true;
  if (this->Stopping() || !this->Reset()) return false;
  r = this->Command("INIT", "", this->Opts.CommandTimeoutMs, this->Opts.Retries);
  if (!r.Ok()) this->Fail(Describe("INIT", r));
  return r.Ok();
}

bool NdiTracker::NegotiateLink() {
  const int timeout = this->Opts.CommandTimeoutMs, retries = this->Opts.Retries;
  ndi::ParseResult r = this->Command("GETINFO", "Features.Firmware.Version", timeout, retries);
  if (r.Code == ndi::ParseCode::DeviceError) --this->DeviceErrors;  // expected on Spectra/Vicra: old API
  if (!r.Ok()) r = this->Command("VER", "0", timeout, retries);
  if (!r.Ok()) return this->Fail(Describe("VER", r)), false;
  {
    std::lock_guard<std::mutex> lock(this->VersionMutex);
    this->Version.assign(this->Payload, this->PayloadLength);
  }

  // Fastest baud both ends can do; ERROR06 from the device means "try slower".
  static const struct { char Code; int Baud; } kRates[] = {
      {'7', 1228739}, {'6', 921600}, {'A', 230400}, {'5', 115200}, {'4', 57600}, {'3', 38400}, {'2', 19200}};
  for (const auto& rate : kRates) {
    if (!this->Transport->HasBaudRate()) break;  // TCP: no COMM
    if (rate.Baud > this->Opts.MaxBaud) continue;
    if (!this->Transport->SetBaudRate(rate.Baud) || !this->Transport->SetBaudRate(9600)) continue;
    const char args[6] = {rate.Code, '0', '0', '0', '0', '\0'};
    r = this->Command("COMM", args, timeout, retries);
    if (r.Code == ndi::ParseCode::DeviceError && r.DeviceError == 0x06) continue;
    if (!r.Ok()) return this->Fail(Describe("COMM", r)), false;
    this->Worker.Sleep(0.1);  // the device switches after its reply
    this->Transport->SetBaudRate(rate.Baud);
    this->Baud = rate.Baud;
    break;
  }
  if (this->Opts.RateCode >= 0) {
    const std::string args = std::to_string(this->Opts.RateCode);
    r = this->Command("IRATE", args.c_str(), timeout, retries);
    if (!r.Ok()) return this->Fail(Describe("IRATE", r)), false;
  }
  return true;
}

bool NdiTracker::Configure() {
  if (!this->NegotiateLink()) return false;
  const int timeout = this->Opts.CommandTimeoutMs, retries = this->Opts.Retries;
  ndi::ParseResult r;
  // Free handles left over from an earlier session.
  uint8_t handles[ndi::MaxHandles];
  int count = 0;
  r = this->Command("PHSR", "01", timeout, retries);
  if (!r.Ok() || !ndi::ParsePhsr(this->Payload, this->PayloadLength, handles, ndi::MaxHandles, count).Ok())
    return this->Fail(Describe("PHSR:01", r)), false;
  for (int i = 0; i < count; ++i) {
    char args[3];
    ndi::WriteHex(args, handles[i], 2);
    args[2] = '\0';
    this->Command("PHF", args, timeout, retries);
  }

  std::fill(std::begin(this->HandleSlot), std::end(this->HandleSlot), -1);
  std::fill(std::begin(this->LastFrame), std::end(this->LastFrame), 0u);
  this->HandlesToFree.clear();
  std::string problems;
  // The definition, zero-padded to 1024 bytes, in 64-byte chunks, onto a port handle.
  auto writeRom = [&](const Tool& tool, uint32_t handle) {
    uint8_t image[1024] = {};
    std::memcpy(image, tool.Rom.data(), std::min<size_t>(tool.Rom.size(), sizeof image));
    for (uint32_t address = 0; address < 1024; address += 64) {
      char args[2 + 4 + 128 + 1];
      ndi::WriteHex(args, handle, 2);
      ndi::WriteHex(args + 2, address, 4);
      for (int i = 0; i < 64; ++i) ndi::WriteHex(args + 6 + 2 * i, image[address + static_cast<uint32_t>(i)], 2);
      args[134] = '\0';
      r = this->Command("PVWR", args, timeout, retries);
      if (!r.Ok()) return this->Fail(tool.Name + ": " + Describe("PVWR", r)), false;
    }
    return true;
  };
  auto assign = [&](const Tool& tool, uint32_t handle) {
    const std::string slotName = ToolToTrackerName(tool.Name);
    this->HandleSlot[handle] = this->Table.Find(slotName.c_str(), slotName.size());
    if (!tool.Rom.empty()) this->HandlesToFree.push_back(static_cast<uint8_t>(handle));  // a wired tool keeps its port's
  };
  bool anyWired = false;
  for (size_t t = 0; t < this->Opts.Tools.size(); ++t) {
    const Tool& tool = this->Opts.Tools[t];
    std::string romError;
    if ((tool.WiredPort < 0 || !tool.Rom.empty()) && !rom::Validate(tool.Rom, romError)) {
      problems += tool.Name + ": " + romError + "; ";
      continue;
    }
    if (tool.WiredPort >= 0) {  // found by its port below
      anyWired = true;
      continue;
    }
    r = this->Command("PHRQ", "*********1****", timeout, retries);
    uint32_t handle;
    if (!r.Ok() || this->PayloadLength < 2 || !ndi::ParseHex(this->Payload, 2, handle))
      return this->Fail(Describe("PHRQ", r)), false;
    if (!writeRom(tool, handle)) return false;
    assign(tool, handle);
  }
  // Wired tools: the device gives each occupied port a handle; PHINF's port location says which
  // port (as PLUS finds them). A virtual SROM, when given, goes over the tool's own before PINIT.
  if (anyWired) {
    r = this->Command("PHSR", "00", timeout, retries);
    if (!r.Ok() || !ndi::ParsePhsr(this->Payload, this->PayloadLength, handles, ndi::MaxHandles, count).Ok())
      return this->Fail(Describe("PHSR:00", r)), false;
    std::vector<int> wiredHandle(this->Opts.Tools.size(), -1);
    for (int i = 0; i < count; ++i) {
      char args[7];
      ndi::WriteHex(args, handles[i], 2);
      std::memcpy(args + 2, "0021", 5);
      r = this->Command("PHINF", args, timeout, retries);
      ndi::PortLocation location;
      if (!r.Ok() || !ndi::ParsePhinfPortLocation(this->Payload, this->PayloadLength, location).Ok() || !location.Wired)
        continue;  // unoccupied, wireless, or a reply we cannot read: not a wired tool of ours
      for (size_t t = 0; t < this->Opts.Tools.size(); ++t)
        if (this->Opts.Tools[t].WiredPort == location.WiredPort && wiredHandle[t] < 0) wiredHandle[t] = handles[i];
    }
    for (size_t t = 0; t < this->Opts.Tools.size(); ++t) {
      const Tool& tool = this->Opts.Tools[t];
      if (tool.WiredPort < 0) continue;
      if (wiredHandle[t] < 0) {
        problems += tool.Name + ": no tool in " + ndi::DescribeWiredPort(tool.WiredPort) + " (PortName " +
                    std::to_string(tool.WiredPort) + "): is it plugged in?; ";
        continue;
      }
      const uint32_t handle = static_cast<uint32_t>(wiredHandle[t]);
      if (!tool.Rom.empty() && !writeRom(tool, handle)) return false;
      assign(tool, handle);
    }
  }
  for (int pass = 0; pass < 3; ++pass) {
    r = this->Command("PHSR", "02", timeout, retries);
    if (!r.Ok() || !ndi::ParsePhsr(this->Payload, this->PayloadLength, handles, ndi::MaxHandles, count).Ok())
      return this->Fail(Describe("PHSR:02", r)), false;
    if (count == 0) break;
    for (int i = 0; i < count; ++i) {
      char args[3];
      ndi::WriteHex(args, handles[i], 2);
      args[2] = '\0';
      r = this->Command("PINIT", args, timeout, retries);
      if (!r.Ok()) problems += std::string("PINIT ") + args + ": " + Describe("PINIT", r) + "; ";
    }
  }
  r = this->Command("PHSR", "03", timeout, retries);
  if (!r.Ok() || !ndi::ParsePhsr(this->Payload, this->PayloadLength, handles, ndi::MaxHandles, count).Ok())
    return this->Fail(Describe("PHSR:03", r)), false;
  for (int i = 0; i < count; ++i) {
    char args[8];
    ndi::WriteHex(args, handles[i], 2);
    std::memcpy(args + 2, "0001", 5);
    this->Command("PHINF", args, timeout, retries);
    args[2] = 'D';
    args[3] = '\0';
    r = this->Command("PENA", args, timeout, retries);
    if (!r.Ok()) return this->Fail(Describe("PENA", r)), false;
  }
  r = this->Command("TSTART", "", timeout, retries);
  if (!r.Ok()) return this->Fail(Describe("TSTART", r)), false;
  if (!problems.empty()) this->Fail(problems);
  return true;
}

bool NdiTracker::ProcessTrackingFrame(uint32_t& lastFrame) {
  const ndi::ParseResult r = this->Opts.Binary ? ndi::ParseBx(this->Rx, this->FrameLength, this->Reply)
                                               : ndi::ParseTx(this->Rx, this->FrameLength, this->Reply);
  if (r.Code == ndi::ParseCode::BadCrc) {
    ++this->CrcErrors;
    return true;
  }
  if (r.Code == ndi::ParseCode::DeviceError) {
    ++this->DeviceErrors;
    if (r.DeviceError == 0x0C || r.DeviceError == 0x10) {  // reset under us: set up again
      this->Fail("tracker left tracking mode (ERROR" + std::to_string(r.DeviceError) + "), reconfiguring");
      return false;
    }
    return true;
  }
  if (!r.Ok()) {
    ++this->Malformed;
    return true;
  }
  ++this->Frames;
  const double now = SteadySeconds();
  uint32_t frame = 0;
  for (int i = 0; i < this->Reply.Count; ++i) frame = std::max(frame, this->Reply.Handles[i].Frame);
  if (frame != 0 && lastFrame != 0 && frame > lastFrame + 1) this->FrameGaps += frame - lastFrame - 1;
  if (frame != 0 && frame <= lastFrame) return true;  // polled faster than the camera: nothing new
  if (frame != 0) lastFrame = frame;
  for (int i = 0; i < this->Reply.Count; ++i) {
    const ndi::HandleReport& h = this->Reply.Handles[i];
    const int slot = this->HandleSlot[h.Handle];
    if (slot < 0) continue;
    ToolPose pose;
    pose.Timestamp = now;
    pose.ReceiveTime = now;
    pose.Frame = h.Frame;
    pose.PortStatus = h.PortStatus;
    switch (h.State) {
      case ndi::HandleState::Valid: pose.State = h.OutOfVolume() ? ToolState::OutOfVolume : ToolState::OK; break;
      case ndi::HandleState::Missing: pose.State = ToolState::Missing; break;
      default: pose.State = ToolState::Disabled; break;
    }
    if (h.State == ndi::HandleState::Valid) {
      std::copy(h.Quaternion, h.Quaternion + 4, pose.Quaternion);
      std::copy(h.Translation, h.Translation + 3, pose.Translation);
      pose.Error = h.Error;
    }
    this->Table.Publish(slot, pose);
  }
  this->Ready.Notify();
  return true;
}

void NdiTracker::TrackLoop() {
  char command[32];
  const size_t length = this->Opts.Binary ? ndi::FormatCommand(command, sizeof command, "BX", "0801")
                                          : ndi::FormatCommand(command, sizeof command, "TX", "0001");
  const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(1.0 / std::max(1.0, this->Opts.PollHz)));
  auto next = std::chrono::steady_clock::now();
  int consecutiveTimeouts = 0;
  uint32_t lastFrame = 0;
  uint64_t polls = 0;
  while (!this->Stopping()) {
    // Replies that came late (a slow device, after we timed out) are still good data: take them
    // now, so that the reply read next belongs to the poll sent next.
    int pending;
    while ((pending = this->ReadFrame(0)) == 0) {
      ++this->LateReplies;
      if (!this->ProcessTrackingFrame(lastFrame)) return;
    }
    if (pending < 0 || !this->Transport->Write(command, length)) {
      this->Fail("tracker unplugged: " + this->Transport->LastError());
      return;
    }
    const int read = this->ReadFrame(this->Opts.TrackingTimeoutMs);
    if (read < 0) {
      this->Fail("tracker unplugged: " + this->Transport->LastError());
      return;
    }
    if (read == 1) {
      ++this->Timeouts;  // keep any partial reply: its rest may still come
      if (++consecutiveTimeouts >= this->Opts.MaxConsecutiveTimeouts) {
        this->Fail("tracker stopped answering (" + std::to_string(consecutiveTimeouts) + " timeouts)");
        return;
      }
    } else {
      consecutiveTimeouts = 0;
      if (!this->ProcessTrackingFrame(lastFrame)) return;
    }
    if (++polls % 32 == 0) this->UpdateCpu();
    next += period;
    const auto now = std::chrono::steady_clock::now();
    if (next < now) next = now;  // fell behind: do not burst to catch up
    std::this_thread::sleep_until(next);
  }
}

void NdiTracker::Shutdown() {
  const int timeout = 500;
  this->ShuttingDown = true;  // let the few stop commands through
  this->Command("TSTOP", "", timeout, 0);
  for (uint8_t h : this->HandlesToFree) {
    char args[3];
    ndi::WriteHex(args, h, 2);
    args[2] = '\0';
    this->Command("PHF", args, timeout, 0);
  }
  if (this->Baud != 9600) {
    this->Command("COMM", "00000", timeout, 0);
    this->Transport->SetBaudRate(9600);
  }
  this->ShuttingDown = false;
}

}  // namespace rp
