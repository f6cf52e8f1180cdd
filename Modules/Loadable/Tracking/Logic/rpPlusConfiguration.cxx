#include "rpPlusConfiguration.h"

#include <strings.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <set>

#include <vtkXMLDataElement.h>

#include "rpNdiProtocol.h"
#include "rpNdiRom.h"
#include "rpNetworkAddress.h"
#include "rpXmlDocument.h"

namespace rp {
namespace plus {

namespace {
namespace fs = std::filesystem;

bool Same(const char* a, const char* b) { return a && b && strcasecmp(a, b) == 0; }
std::string Attr(vtkXMLDataElement* e, const char* name) {
  const char* v = e->GetAttribute(name);
  return v ? std::string(v) : std::string();
}
bool Has(vtkXMLDataElement* e, const char* name) { return e->GetAttribute(name) != nullptr; }

bool ParseInt(const std::string& text, long lo, long hi, long& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtol(text.c_str(), &end, 10);
  while (end && (*end == ' ' || *end == '\t')) ++end;
  return end && *end == '\0' && value >= lo && value <= hi;
}
bool ParseDouble(const std::string& text, double& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  while (end && (*end == ' ' || *end == '\t')) ++end;
  return end && *end == '\0' && std::isfinite(value);
}
bool ParseBool(const std::string& text, bool& value) {  // PLUS: TRUE/FALSE in any case
  if (strcasecmp(text.c_str(), "true") == 0) return value = true, true;
  if (strcasecmp(text.c_str(), "false") == 0) return value = false, true;
  return false;
}
bool ParseMatrix(const std::string& text, double m[16], std::string& why) {
  const char* p = text.c_str();
  int n = 0;
  for (;;) {
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r') ++p;
    if (*p == '\0') break;
    char* end = nullptr;
    const double v = std::strtod(p, &end);
    if (end == p || !std::isfinite(v)) return why = "Matrix has a value that is not a number", false;
    if (n == 16) return why = "Matrix has more than 16 values", false;
    m[n++] = v;
    p = end;
  }
  if (n != 16) return why = "Matrix has " + std::to_string(n) + " values, not 16", false;
  if (m[12] != 0 || m[13] != 0 || m[14] != 0 || m[15] != 1) return why = "Matrix's last row is not 0 0 0 1", false;
  return true;
}

// Why a device type is not driven, by family (PLUS's device names).
std::string WhyNotDriven(const std::string& type) {
  static const std::map<std::string, std::string> kWhy = {
      {"VirtualMixer", "a PLUS channel mixer: RoboPlan serves the tracker's transforms directly"},
      {"VirtualCapture", "PLUS recording to file: use `roboplan track --record`"},
      {"VirtualDiscCapture", "PLUS recording to file: use `roboplan track --record`"},
      {"SavedDataSource", "replays a PLUS recording: use `roboplan track --replay`"},
      {"FakeTracker", "PLUS's simulated tracker: use `roboplan track --simulate`"},
      {"OpenIGTLinkTracker", "an OpenIGTLink client: use `roboplan track --igtl HOST:PORT`"},
  };
  const auto it = kWhy.find(type);
  if (it != kWhy.end()) return it->second;
  static const char* kImaging[] = {"Epiphan", "OpenCVVideo", "MmfVideo", "VFWVideo", "SonixVideo", "SonixPorta",
                                   "BkProFocusOem", "ICCapturing", "IntersonVideo", "IntersonSDKCxxVideo",
                                   "TelemedVideo", "CapistranoVideo", "WinProbeVideo", "UsSimulator", "ImageProcessor",
                                   "VirtualVolumeReconstructor", "RealSenseCamera", "OvrvisionPro", "InfraredSeekCam"};
  for (const char* t : kImaging)
    if (type == t) return "video/ultrasound capture is not driven by RoboPlan (tracking only)";
  if (type.find("Tracker") != std::string::npos || type == "OptiTrack" || type == "MicronTracker" || type == "Ascension3DG")
    return "a tracker RoboPlan has no driver for (NDI trackers only)";
  return "a PLUS device RoboPlan does not drive";
}

std::vector<std::string> SearchFolders(const std::string& source, const ResolveOptions& options) {
  std::vector<std::string> folders;
  if (!options.DeviceSetConfigurationDirectory.empty()) folders.push_back(options.DeviceSetConfigurationDirectory);
  std::error_code ec;
  fs::path folder = fs::absolute(fs::path(source), ec).parent_path();
  for (int level = 0; level < 4 && !folder.empty(); ++level) {
    folders.push_back(folder.string());
    if (folder == folder.parent_path()) break;
    folder = folder.parent_path();
  }
  return folders;
}

void ResolveRom(Tool& tool, const std::string& source, const ResolveOptions& options) {
  const fs::path rom(tool.RomFile);
  std::vector<std::string> candidates;
  if (rom.is_absolute()) candidates.push_back(rom.lexically_normal().string());
  else
    for (const std::string& folder : SearchFolders(source, options))
      candidates.push_back((fs::path(folder) / rom).lexically_normal().string());
  for (const std::string& candidate : candidates) {
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec)) {
      tool.RomPath = candidate;
      return;
    }
  }
  tool.RomTried = candidates;
}

void ReadTool(vtkXMLDataElement* e, NdiTracker& device, std::set<std::string>& ids, const std::string& source,
              const ResolveOptions& options, Configuration& c) {
  const std::string where = "Device " + device.Id + ": ";
  Tool tool;
  tool.Id = Attr(e, "Id");
  tool.PortName = Attr(e, "PortName");
  tool.RomFile = Attr(e, "RomFile");
  if (tool.Id.empty()) return c.Refused.push_back({where + "a tool DataSource", "it has no Id"});
  if (!ids.insert(tool.Id).second) return c.Refused.push_back({where + "tool " + tool.Id, "a second tool with that Id"});
  if (!tool.PortName.empty()) {  // a wired tool (Aurora sensor, Polaris active tool), as PLUS reads PortName
    if (!ndi::ParseWiredPort(tool.PortName, tool.WiredPort))
      return c.Refused.push_back({where + "tool " + tool.Id, "PortName \"" + tool.PortName + "\" is not a wired port number (an integer >= 0)"});
    if (tool.RomFile.empty()) return device.Tools.push_back(tool);  // the SROM in the tool defines it
  }
  if (tool.RomFile.empty())
    return c.Refused.push_back({where + "tool " + tool.Id, "neither a RomFile (a passive tool) nor a PortName (a wired tool)"});
  ResolveRom(tool, source, options);
  if (tool.RomPath.empty()) {
    std::string tried;
    for (const auto& t : tool.RomTried) tried += (tried.empty() ? "" : ", ") + t;
    return c.Refused.push_back({where + "tool " + tool.Id, "RomFile " + tool.RomFile + " not found (tried " + tried + ")"});
  }
  try {
    rom::ReadFile(tool.RomPath);  // checksum, marker count, ...
  } catch (const std::exception& ex) {
    return c.Refused.push_back({where + "tool " + tool.Id, std::string("bad ROM: ") + ex.what()});
  }
  device.Tools.push_back(tool);
}

// Attributes of an NDI device we read; the others are named as ignored.
const std::set<std::string>& HonouredDeviceAttributes() {
  static const std::set<std::string> kNames = {"Id", "Type", "SerialPort", "BaudRate", "NetworkHostname", "NetworkPort",
                                               "ToolReferenceFrame", "AcquisitionRate"};
  return kNames;
}

void ReadNdiDevice(vtkXMLDataElement* e, int index, const std::string& source, const ResolveOptions& options,
                   Configuration& c) {
  NdiTracker d;
  d.Type = Attr(e, "Type");
  d.Id = Has(e, "Id") ? Attr(e, "Id") : d.Type + std::to_string(index);
  const std::string where = "Device " + d.Id + " (" + d.Type + ")";
  long number = 0;
  double value = 0;
  d.SerialPort = Attr(e, "SerialPort");
  if (!d.SerialPort.empty()) {
    if (d.SerialPort[0] == '/') d.SerialDevice = d.SerialPort;  // a device path (not PLUS's syntax, but clear)
    else if (ParseInt(d.SerialPort, 1, 1000, number)) d.SerialDevice = SerialDeviceForPort(static_cast<int>(number));
    if (d.SerialDevice.empty())
      c.Refused.push_back({where + " SerialPort=\"" + d.SerialPort + "\"",
                           "no Linux device for it (PLUS/ndicapi: 1-2 /dev/ttyS0-1, 3-8 /dev/ttyUSB0-5): give --serial"});
  }
  if (Has(e, "BaudRate")) {
    static const std::set<long> kBauds = {9600, 14400, 19200, 38400, 57600, 115200, 921600, 1228739};
    if (ParseInt(Attr(e, "BaudRate"), 1, 10000000, number) && kBauds.count(number)) d.BaudRate = static_cast<int>(number);
    else c.Refused.push_back({where + " BaudRate=\"" + Attr(e, "BaudRate") + "\"", "not an NDI baud rate"});
  }
  d.NetworkHostname = Attr(e, "NetworkHostname");
  if (Has(e, "NetworkPort")) {
    if (ParseInt(Attr(e, "NetworkPort"), 1, 65535, number)) d.NetworkPort = static_cast<int>(number);
    else c.Refused.push_back({where + " NetworkPort=\"" + Attr(e, "NetworkPort") + "\"", "not a TCP port; 8765 used"});
  }
  if (Has(e, "ToolReferenceFrame") && !Attr(e, "ToolReferenceFrame").empty()) d.ToolReferenceFrame = Attr(e, "ToolReferenceFrame");
  if (Has(e, "AcquisitionRate")) {
    if (ParseDouble(Attr(e, "AcquisitionRate"), value) && value > 0 && value <= 1000) d.AcquisitionRate = value;
    else c.Refused.push_back({where + " AcquisitionRate=\"" + Attr(e, "AcquisitionRate") + "\"", "not a rate in Hz"});
  }
  for (int a = 0; a < e->GetNumberOfAttributes(); ++a) {
    const char* name = e->GetAttributeName(a);
    if (name && !HonouredDeviceAttributes().count(name))
      c.Refused.push_back({where + " " + name + "=\"" + Attr(e, name) + "\"", "attribute not used by RoboPlan"});
  }
  std::set<std::string> ids;
  vtkXMLDataElement* sources = e->FindNestedElementWithName("DataSources");
  for (int i = 0; sources && i < sources->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* s = sources->GetNestedElement(i);
    if (!Same(s->GetName(), "DataSource")) continue;
    if (Same(s->GetAttribute("Type"), "Tool")) ReadTool(s, d, ids, source, options, c);
    else c.Refused.push_back({where + " DataSource " + Attr(s, "Id"), "type '" + Attr(s, "Type") + "' (an NDI tracker has tools)"});
  }
  if (d.Tools.empty()) c.Refused.push_back({where, "no tool it could track"});
  c.Trackers.push_back(d);
}

void ReadDataCollection(vtkXMLDataElement* dc, const std::string& source, const ResolveOptions& options, Configuration& c,
                        std::map<std::string, std::string>& channelOwner) {
  if (vtkXMLDataElement* set = dc->FindNestedElementWithName("DeviceSet")) {
    c.Name = Attr(set, "Name");
    c.Description = Attr(set, "Description");
  }
  int index = 0;
  for (int i = 0; i < dc->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* e = dc->GetNestedElement(i);
    if (!Same(e->GetName(), "Device")) continue;
    ++index;
    const std::string type = Attr(e, "Type"), id = Attr(e, "Id");
    if (vtkXMLDataElement* outputs = e->FindNestedElementWithName("OutputChannels"))
      for (int k = 0; k < outputs->GetNumberOfNestedElements(); ++k)
        channelOwner[Attr(outputs->GetNestedElement(k), "Id")] = id + " (" + type + ")";
    if (type == "NDITracker" || type == "PolarisTracker" || type == "AuroraTracker")
      ReadNdiDevice(e, index, source, options, c);
    else
      c.Refused.push_back({"Device " + (id.empty() ? "#" + std::to_string(index) : id) + " (" + type + ")", WhyNotDriven(type)});
  }
}

void ReadCoordinateDefinitions(vtkXMLDataElement* cd, Configuration& c) {
  for (int i = 0; i < cd->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* e = cd->GetNestedElement(i);
    if (!Same(e->GetName(), "Transform")) continue;
    FixedTransform t;
    t.From = Attr(e, "From");
    t.To = Attr(e, "To");
    const std::string what = "Transform " + (t.From.empty() ? std::string("?") : t.From) + "To" + (t.To.empty() ? "?" : t.To);
    std::string why;
    if (t.From.empty() || t.To.empty()) why = "From and To are both needed";
    else if (!Has(e, "Matrix")) why = "no Matrix";
    else ParseMatrix(Attr(e, "Matrix"), t.Matrix, why);
    if (why.empty() && Has(e, "Error") && !ParseDouble(Attr(e, "Error"), t.Error)) why = "Error is not a number";
    if (!why.empty()) {
      c.Refused.push_back({what, why});
      continue;
    }
    t.Date = Attr(e, "Date");
    c.Transforms.push_back(t);
  }
}

void ReadClientInfo(vtkXMLDataElement* info, Server& s, Configuration& c) {
  for (int i = 0; i < info->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* group = info->GetNestedElement(i);
    for (int k = 0; k < group->GetNumberOfNestedElements(); ++k) {
      vtkXMLDataElement* e = group->GetNestedElement(k);
      if (Same(group->GetName(), "MessageTypes") && Same(e->GetName(), "Message")) {
        const std::string type = Attr(e, "Type");
        if (!type.empty()) s.MessageTypes.push_back(type);
        if (type != "TRANSFORM" && type != "TDATA" && type != "QTDATA")
          c.Refused.push_back({"PlusOpenIGTLinkServer message type " + type, "RoboPlan serves tool poses only (TRANSFORM, TDATA, QTDATA)"});
      } else if (Same(group->GetName(), "TransformNames") && Same(e->GetName(), "Transform")) {
        TransformName t{Attr(e, "Name"), Attr(e, "From"), Attr(e, "To")};
        if (t.Name.empty() && !t.From.empty() && !t.To.empty()) t.Name = t.From + "To" + t.To;
        if (t.Name.empty()) c.Refused.push_back({"PlusOpenIGTLinkServer transform", "no Name (nor From and To)"});
        else s.TransformNames.push_back(t);
      } else if (Same(group->GetName(), "ImageNames") && Same(e->GetName(), "Image")) {
        s.ImageNames.push_back({Attr(e, "Name"), Attr(e, "EmbeddedTransformToFrame")});
        c.Refused.push_back({"PlusOpenIGTLinkServer image " + Attr(e, "Name"), "no image source (tracking only)"});
      } else if (Same(group->GetName(), "StringNames") && Same(e->GetName(), "String")) {
        s.StringNames.push_back(Attr(e, "Name"));
        c.Refused.push_back({"PlusOpenIGTLinkServer string " + Attr(e, "Name"), "no string source"});
      }
    }
  }
}

void ReadServer(vtkXMLDataElement* e, Configuration& c, const std::map<std::string, std::string>& channelOwner) {
  Server& s = c.OpenIGTLinkServer;
  s.Present = true;
  long number = 0;
  double value = 0;
  bool flag = false;
  if (ParseInt(Attr(e, "ListeningPort"), 0, 65535, number)) s.ListeningPort = static_cast<int>(number);
  else c.Refused.push_back({"PlusOpenIGTLinkServer ListeningPort=\"" + Attr(e, "ListeningPort") + "\"",
                            "not a port (PLUS requires one): give --serve PORT"});
  if (Has(e, "ListeningAddress")) {  // ours: PlusServer listens on every interface, RoboPlan on 127.0.0.1 unless told
    Ipv4 address = 0;
    std::string error;
    if (ParseBindAddress(Attr(e, "ListeningAddress"), address, error)) s.ListeningAddress = Attr(e, "ListeningAddress");
    else c.Refused.push_back({"PlusOpenIGTLinkServer ListeningAddress=\"" + Attr(e, "ListeningAddress") + "\"", error + "; 127.0.0.1 is used"});
  }
  s.OutputChannelId = Attr(e, "OutputChannelId");
  const auto owner = channelOwner.find(s.OutputChannelId);
  if (owner == channelOwner.end())
    c.Refused.push_back({"PlusOpenIGTLinkServer OutputChannelId=\"" + s.OutputChannelId + "\"",
                         "no device has that output channel; the NDI trackers' tools are served"});
  else if (owner->second.find("NDITracker)") == std::string::npos && owner->second.find("PolarisTracker)") == std::string::npos &&
           owner->second.find("AuroraTracker)") == std::string::npos)
    c.Refused.push_back({"PlusOpenIGTLinkServer OutputChannelId=\"" + s.OutputChannelId + "\"",
                         "the channel of " + owner->second + ", not set up; the NDI trackers' tools are served"});
  if (Has(e, "SendValidTransformsOnly") && ParseBool(Attr(e, "SendValidTransformsOnly"), flag)) s.SendValidTransformsOnly = flag;
  if (Has(e, "KeepAliveIntervalSec") && ParseDouble(Attr(e, "KeepAliveIntervalSec"), value) && value > 0) s.KeepAliveIntervalSec = value;
  if (Has(e, "MaxNumberOfIgtlMessagesToSend") && ParseInt(Attr(e, "MaxNumberOfIgtlMessagesToSend"), 1, 1000000, number))
    s.MaxNumberOfIgtlMessagesToSend = static_cast<int>(number);
  if (Has(e, "MaxTimeSpentWithProcessingMs") && ParseDouble(Attr(e, "MaxTimeSpentWithProcessingMs"), value))
    s.MaxTimeSpentWithProcessingMs = value;
  if (Has(e, "DefaultClientSendTimeoutSec") && ParseDouble(Attr(e, "DefaultClientSendTimeoutSec"), value))
    s.DefaultClientSendTimeoutSec = value;
  if (vtkXMLDataElement* info = e->FindNestedElementWithName("DefaultClientInfo")) ReadClientInfo(info, s, c);
}
}  // namespace

std::string SerialDeviceForPort(int n) {
  if (n == 1 || n == 2) return "/dev/ttyS" + std::to_string(n - 1);
  if (n >= 3 && n <= 8) return "/dev/ttyUSB" + std::to_string(n - 3);
  return {};
}

std::string Configuration::RefusedMessage() const {
  if (this->Refused.empty()) return {};
  std::string text = "not set up from " + this->Source + ":";
  for (const Refusal& r : this->Refused) text += "\n  " + r.What + ": " + r.Why;
  return text;
}

void ReadOptionalNumber(vtkXMLDataElement* e, const char* name, std::optional<double>& value, Configuration& c) {
  if (!Has(e, name)) return;
  double v = 0;
  if (ParseDouble(Attr(e, name), v)) value = v;
  else c.Refused.push_back({std::string(e->GetName()) + " " + name + "=\"" + Attr(e, name) + "\"", "not a number"});
}

void ReadPhantomDefinition(vtkXMLDataElement* phantom, Configuration& c) {
  vtkXMLDataElement* geometry = phantom->FindNestedElementWithName("Geometry");
  vtkXMLDataElement* landmarks = geometry ? geometry->FindNestedElementWithName("Landmarks") : nullptr;
  if (!landmarks) return;
  PhantomRegistrationSettings& p = c.PhantomRegistration;
  p.HasLandmarks = true;
  for (int i = 0; i < landmarks->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* l = landmarks->GetNestedElement(i);
    if (!Same(l->GetName(), "Landmark")) continue;
    PhantomLandmark landmark;
    std::istringstream in(Attr(l, "Position"));
    if (!(in >> landmark.Position[0] >> landmark.Position[1] >> landmark.Position[2])) {
      if (p.LandmarkProblem.empty()) p.LandmarkProblem = "landmark #" + std::to_string(i + 1) + " has no Position=\"x y z\"";
      continue;
    }
    landmark.Name = Has(l, "Name") ? Attr(l, "Name") : "#" + std::to_string(i + 1);
    p.Landmarks.push_back(landmark);
  }
}

void ReadPhantomAlgorithms(vtkXMLDataElement* root, Configuration& c) {
  PhantomRegistrationSettings& p = c.PhantomRegistration;
  if (vtkXMLDataElement* phantom = root->FindNestedElementWithName("PhantomDefinition")) ReadPhantomDefinition(phantom, c);
  if (vtkXMLDataElement* a = root->FindNestedElementWithName("vtkPlusPhantomLandmarkRegistrationAlgo")) {
    p.PhantomFrame = Attr(a, "PhantomCoordinateFrame");
    p.ReferenceFrame = Attr(a, "ReferenceCoordinateFrame");
    p.StylusTipFrame = Attr(a, "StylusTipCoordinateFrame");
    ReadOptionalNumber(a, "AcquisitionRate", p.AcquisitionRate, c);
    ReadOptionalNumber(a, "FilterWindowTimeSec", p.FilterWindowTimeSec, c);
    ReadOptionalNumber(a, "DetectionTimeSec", p.DetectionTimeSec, c);
    ReadOptionalNumber(a, "StylusShaftMinimumDisplacementThresholdMm", p.StylusShaftMinimumDisplacementThresholdMm, c);
    ReadOptionalNumber(a, "StylusTipMaximumDisplacementThresholdMm", p.StylusTipMaximumDisplacementThresholdMm, c);
  }
  if (vtkXMLDataElement* pivot = root->FindNestedElementWithName("vtkPlusPivotCalibrationAlgo"))
    p.StylusFrame = Attr(pivot, "ObjectMarkerCoordinateFrame");
}

bool ReadConfigurationElement(vtkXMLDataElement* root, const std::string& source, const ResolveOptions& options,
                              Configuration& c, std::string& error) {
  c = Configuration();
  c.Source = source;
  if (!root || !Same(root->GetName(), "PlusConfiguration")) {
    error = source + ": not a PLUS configuration (the root element is <" + std::string(root && root->GetName() ? root->GetName() : "?") +
            ">, expected <PlusConfiguration>)";
    return false;
  }
  c.Version = Attr(root, "version");
  std::map<std::string, std::string> channelOwner;
  vtkXMLDataElement* server = nullptr;
  for (int i = 0; i < root->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* e = root->GetNestedElement(i);
    const std::string name = e->GetName() ? e->GetName() : "";
    if (name == "DataCollection") ReadDataCollection(e, source, options, c, channelOwner);
    else if (name == "CoordinateDefinitions") ReadCoordinateDefinitions(e, c);
    else if (name == "PlusOpenIGTLinkServer") server = e;  // after the devices: it names their channels
    else c.Refused.push_back({"<" + name + ">", "not used by `roboplan track`"});
  }
  if (server) ReadServer(server, c, channelOwner);
  ReadPhantomAlgorithms(root, c);  // `roboplan phantom-registration`'s (refused above for track)
  return true;
}

bool ParseConfiguration(const std::string& text, const std::string& source, const ResolveOptions& options,
                        Configuration& c, std::string& error) {
  vtkSmartPointer<vtkXMLDataElement> root = ParseXml(text, source, error);
  if (!root) return false;
  return ReadConfigurationElement(root, source, options, c, error);
}

bool ParseClientInfo(const std::string& xml, Server& info, std::string& error) {
  vtkSmartPointer<vtkXMLDataElement> root = ParseXml(xml, "CLIENTINFO", error);
  if (!root) return false;
  if (!Same(root->GetName(), "ClientInfo")) {
    error = std::string("CLIENTINFO holds <") + (root->GetName() ? root->GetName() : "") + ">, not <ClientInfo>";
    return false;
  }
  Server parsed;
  Configuration ignored;  // refusals name what we cannot serve; a client's wishes are not errors
  ReadClientInfo(root, parsed, ignored);
  info.MessageTypes = std::move(parsed.MessageTypes);
  info.TransformNames = std::move(parsed.TransformNames);
  info.ImageNames = std::move(parsed.ImageNames);
  info.StringNames = std::move(parsed.StringNames);
  return true;
}

bool ReadConfiguration(const std::string& path, const ResolveOptions& options, Configuration& c, std::string& error) {
  vtkSmartPointer<vtkXMLDataElement> root = ReadXmlFile(path, error, std::size_t(16) << 20);
  if (!root) return false;
  return ReadConfigurationElement(root, path, options, c, error);
}

nlohmann::json ToJson(const Configuration& c) {
  nlohmann::json doc = {{"source", c.Source}, {"version", c.Version}, {"name", c.Name}};
  doc["trackers"] = nlohmann::json::array();
  for (const NdiTracker& d : c.Trackers) {
    nlohmann::json t = {{"id", d.Id}, {"type", d.Type}, {"toolReferenceFrame", d.ToolReferenceFrame}};
    if (d.Tcp()) t["network"] = {{"host", d.NetworkHostname}, {"port", d.NetworkPort}};
    else t["serial"] = {{"serialPort", d.SerialPort}, {"device", d.SerialDevice}, {"baudRate", d.BaudRate}};
    if (d.AcquisitionRate > 0) t["acquisitionRateHz"] = d.AcquisitionRate;
    t["tools"] = nlohmann::json::array();
    for (const Tool& tool : d.Tools) {
      nlohmann::json j = {{"id", tool.Id}, {"transform", tool.Id + "To" + d.ToolReferenceFrame}, {"romFile", tool.RomFile},
                          {"romPath", tool.RomPath}};
      if (tool.WiredPort >= 0) j["wiredPort"] = tool.WiredPort;
      t["tools"].push_back(j);
    }
    doc["trackers"].push_back(t);
  }
  doc["transforms"] = nlohmann::json::array();
  for (const FixedTransform& t : c.Transforms) {
    nlohmann::json j = {{"name", t.From + "To" + t.To}, {"from", t.From}, {"to", t.To},
                        {"matrix", std::vector<double>(t.Matrix, t.Matrix + 16)}, {"date", t.Date}};
    if (t.Error >= 0) j["error"] = t.Error;
    doc["transforms"].push_back(j);
  }
  const Server& s = c.OpenIGTLinkServer;
  if (s.Present) {
    nlohmann::json names = nlohmann::json::array();
    for (const TransformName& n : s.TransformNames) names.push_back(n.Name);
    doc["server"] = {{"listeningPort", s.ListeningPort}, {"listeningAddress", s.ListeningAddress.empty() ? "127.0.0.1" : s.ListeningAddress},
                     {"outputChannelId", s.OutputChannelId},
                     {"sendValidTransformsOnly", s.SendValidTransformsOnly}, {"keepAliveIntervalSec", s.KeepAliveIntervalSec},
                     {"messageTypes", s.MessageTypes}, {"transformNames", names}};
  }
  doc["refused"] = nlohmann::json::array();
  for (const Refusal& r : c.Refused) doc["refused"].push_back({{"what", r.What}, {"why", r.Why}});
  return doc;
}

}  // namespace plus
}  // namespace rp
