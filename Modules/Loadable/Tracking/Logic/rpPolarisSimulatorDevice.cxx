#include "rpPolarisSimulatorDevice.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "rpNdiProtocol.h"
#include "rpToolPose.h"

namespace rp {

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

PolarisSimulatorDevice::PolarisSimulatorDevice(const PolarisSimulatorOptions& options, PolarisSimulatorTools& tools,
                                               Sender send)
    : Opts(options), Tools(tools), Send(std::move(send)), Rate(options.FrameRate), Rng(options.Seed) {}

void PolarisSimulatorDevice::PowerOn(double startTime) {
  this->StartTime = startTime;
  this->PowerOnReset();
}

double PolarisSimulatorDevice::Now() const { return SteadySeconds() - this->StartTime; }

PolarisSimulatorCounters PolarisSimulatorDevice::GetCounters() const {
  std::lock_guard<std::mutex> lock(this->CountersMutex);
  return this->Count;
}

void PolarisSimulatorDevice::Break(bool accept) {
  {
    std::lock_guard<std::mutex> lock(this->CountersMutex);
    ++this->Count.Breaks;
  }
  if (accept) {
    this->PowerOnReset();
    this->Reply("RESET");
  }
}

void PolarisSimulatorDevice::Receive(const char* data, size_t length) {
  this->Input.append(data, length);
  if (this->Input.size() > 65536) this->Input.clear();  // garbage: nobody sends this much
  size_t cr;
  while ((cr = this->Input.find('\r')) != std::string::npos) {
    const std::string line = this->Input.substr(0, cr);
    this->Input.erase(0, cr + 1);
    this->HandleCommand(line.data(), line.size());
  }
}

void PolarisSimulatorDevice::LoadPluggedSrom(Handle& h) const {
  const auto& srom = this->Tools[static_cast<size_t>(h.WiredTool)].Definition.Rom;
  std::fill(h.Rom.begin(), h.Rom.end(), uint8_t{0});
  std::copy(srom.begin(), srom.begin() + static_cast<long>(std::min(srom.size(), h.Rom.size())), h.Rom.begin());
}

void PolarisSimulatorDevice::PowerOnReset() {
  this->Handles.clear();
  {  // each occupied wired port has a handle from power-on (01, 02, ...), its SROM the tool's
    for (size_t t = 0; t < this->Tools.Size(); ++t) {
      if (this->Tools[t].WiredPort < 0) continue;
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

void PolarisSimulatorDevice::Reply(const char* payload) {
  std::string text(payload);
  char crc[4];
  ndi::WriteHex(crc, ndi::Crc16(text.data(), text.size()), 4);
  text.append(crc, 4);
  text += '\r';
  this->Send(reinterpret_cast<uint8_t*>(&text[0]), text.size(), true);
}

void PolarisSimulatorDevice::ReplyError(int code) {
  char text[8] = "ERROR";
  ndi::WriteHex(text + 5, static_cast<uint32_t>(code), 2);
  text[7] = '\0';
  this->Reply(text);
}

void PolarisSimulatorDevice::ReplyBinary(const uint8_t* body, size_t length) {
  std::vector<uint8_t> frame(length + 8);
  frame[0] = 0xC4;
  frame[1] = 0xA5;
  PutU16(&frame[2], static_cast<uint16_t>(length));
  PutU16(&frame[4], ndi::Crc16(frame.data(), 4));
  std::memcpy(&frame[6], body, length);
  PutU16(&frame[6 + length], ndi::Crc16(body, length));
  this->Send(frame.data(), frame.size(), false);
}

PolarisSimulatorDevice::Handle* PolarisSimulatorDevice::FindHandle(const char* hex) {
  uint32_t number;
  if (!ndi::ParseHex(hex, 2, number)) return nullptr;
  for (auto& h : this->Handles)
    if (h.Number == static_cast<int>(number)) return &h;
  return nullptr;
}

uint32_t PolarisSimulatorDevice::CurrentFrame() const {
  return static_cast<uint32_t>(std::floor((this->Now() - this->TrackingStart) * this->Rate)) + 1;
}

// The NDI commands the simulator answers, one handler each (as PLUS's and NDI's simulators do); a
// command not listed answers ERROR01, and any command but these first five needs INIT (ERROR10).
struct PolarisSimulatorDevice::CommandEntry {
  const char* Name;
  bool NeedsInit;
  CommandHandler Run;
};

const PolarisSimulatorDevice::CommandEntry PolarisSimulatorDevice::CommandTable[] = {
    {"RESET", false, &PolarisSimulatorDevice::OnReset},     {"INIT", false, &PolarisSimulatorDevice::OnInit},
    {"GETINFO", false, &PolarisSimulatorDevice::OnGetInfo}, {"VER", false, &PolarisSimulatorDevice::OnVersion},
    {"COMM", false, &PolarisSimulatorDevice::OnComm},       {"IRATE", true, &PolarisSimulatorDevice::OnIrate},
    {"VSEL", true, &PolarisSimulatorDevice::OnAcknowledge}, {"BEEP", true, &PolarisSimulatorDevice::OnAcknowledge},
    {"LED", true, &PolarisSimulatorDevice::OnAcknowledge},  {"PHSR", true, &PolarisSimulatorDevice::OnPhsr},
    {"PHRQ", true, &PolarisSimulatorDevice::OnPhrq},        {"PHF", true, &PolarisSimulatorDevice::OnPhf},
    {"PVWR", true, &PolarisSimulatorDevice::OnPvwr},        {"PINIT", true, &PolarisSimulatorDevice::OnPinit},
    {"PHINF", true, &PolarisSimulatorDevice::OnPhinf},      {"PENA", true, &PolarisSimulatorDevice::OnPena},
    {"PDIS", true, &PolarisSimulatorDevice::OnPdis},        {"TSTART", true, &PolarisSimulatorDevice::OnTstart},
    {"TSTOP", true, &PolarisSimulatorDevice::OnTstop},      {"TX", true, &PolarisSimulatorDevice::OnTracking},
    {"BX", true, &PolarisSimulatorDevice::OnTracking},
};

void PolarisSimulatorDevice::HandleCommand(const char* line, size_t length) {
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

bool PolarisSimulatorDevice::SplitCommand(std::string text, std::string& name, std::string& args) {
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

void PolarisSimulatorDevice::OnReset(const std::string&, const std::string&) {
  this->PowerOnReset();
  {
    std::lock_guard<std::mutex> lock(this->CountersMutex);
    ++this->Count.Resets;
  }
  this->Reply("RESET");
}

void PolarisSimulatorDevice::OnInit(const std::string&, const std::string&) {
  this->Initialized = true;
  this->Reply("OKAY");
}

void PolarisSimulatorDevice::OnGetInfo(const std::string&, const std::string&) {
  this->ReplyError(0x01);  // Spectra/Vicra: old API
}

void PolarisSimulatorDevice::OnVersion(const std::string&, const std::string&) {
  this->Reply("Polaris Spectra (RoboPlan simulator)\nFreeze Tag: 1.0\nCombined Firmware Revision: 006");
}

void PolarisSimulatorDevice::OnComm(const std::string&, const std::string& args) {
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

void PolarisSimulatorDevice::OnIrate(const std::string&, const std::string& args) {
  if (args == "0") this->Rate = 20;
  else if (args == "1") this->Rate = 30;
  else if (args == "2") this->Rate = 60;
  else return this->ReplyError(0x23);
  this->Reply("OKAY");
}

void PolarisSimulatorDevice::OnAcknowledge(const std::string& name, const std::string&) {
  this->Reply(name == "BEEP" ? "1" : "OKAY");  // VSEL, BEEP, LED
}

void PolarisSimulatorDevice::OnPhsr(const std::string&, const std::string& args) {
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

void PolarisSimulatorDevice::OnPhrq(const std::string&, const std::string&) {
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

PolarisSimulatorDevice::Handle* PolarisSimulatorDevice::CommandHandle(const std::string& args) {
  if (args.size() < 2) {
    this->ReplyError(0x07);
    return nullptr;
  }
  Handle* h = this->FindHandle(args.c_str());
  if (!h) this->ReplyError(0x2B);
  return h;
}

void PolarisSimulatorDevice::OnPhf(const std::string&, const std::string& args) {
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

void PolarisSimulatorDevice::OnPvwr(const std::string&, const std::string& args) {
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

void PolarisSimulatorDevice::OnPinit(const std::string&, const std::string& args) {
  Handle* h = this->CommandHandle(args);
  if (!h) return;
  std::string error;
  if (!rom::Validate(h->Rom, error)) return this->ReplyError(0x40);
  const auto sameAsPlugged = [&] {
    const auto& srom = this->Tools[static_cast<size_t>(h->WiredTool)].Definition.Rom;
    return srom.size() <= h->Rom.size() && std::equal(srom.begin(), srom.end(), h->Rom.begin());
  };
  // A wired port tracks its own tool unless a virtual SROM of another definition was written over it.
  h->Tool = h->WiredTool >= 0 && sameAsPlugged() ? h->WiredTool : this->Tools.ForRom(h->Rom, this->Opts.VolumeCenter);
  h->Initialized = true;
  {
    std::lock_guard<std::mutex> lock(this->CountersMutex);
    ++this->Count.LoadedTools;
  }
  this->Reply("OKAY");
}

void PolarisSimulatorDevice::OnPhinf(const std::string&, const std::string& args) {
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
    std::string part = tool >= 0 ? this->Tools[static_cast<size_t>(tool)].Definition.PartNumber : "UNKNOWN";
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
      const int port = this->Tools[static_cast<size_t>(h->WiredTool)].WiredPort;
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

void PolarisSimulatorDevice::OnPena(const std::string&, const std::string& args) {
  Handle* h = this->CommandHandle(args);
  if (!h) return;
  if (!h->Initialized) return this->ReplyError(0x0E);
  h->Enabled = true;
  this->Reply("OKAY");
}

void PolarisSimulatorDevice::OnPdis(const std::string&, const std::string& args) {
  Handle* h = this->CommandHandle(args);
  if (!h) return;
  h->Enabled = false;
  this->Reply("OKAY");
}

void PolarisSimulatorDevice::OnTstart(const std::string&, const std::string&) {
  this->Tracking = true;
  this->TrackingStart = this->Now();
  {
    std::lock_guard<std::mutex> lock(this->CountersMutex);
    this->Count.Tracking = true;
  }
  this->Reply("OKAY");
}

void PolarisSimulatorDevice::OnTstop(const std::string&, const std::string&) {
  this->Tracking = false;
  {
    std::lock_guard<std::mutex> lock(this->CountersMutex);
    this->Count.Tracking = false;
  }
  this->Reply("OKAY");
}

void PolarisSimulatorDevice::OnTracking(const std::string& name, const std::string&) {
  if (!this->Tracking) return this->ReplyError(0x0C);
  {
    std::lock_guard<std::mutex> lock(this->CountersMutex);
    ++this->Count.TrackingReplies;
  }
  this->BuildTracking(name == "BX");  // TX or BX
}

void PolarisSimulatorDevice::BuildTracking(bool binary) {
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
    const PolarisSimulatorTools::Tool* tool = h.Tool >= 0 ? &this->Tools[static_cast<size_t>(h.Tool)] : nullptr;
    double m[16];
    if (tool) EvaluateTrajectory(tool->Definition, t, m);
    if (!tool || tool->Occluded || (this->Opts.MarkerVisibility && !PolarisSimulatorTools::MarkersVisible(*tool, m))) {
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
