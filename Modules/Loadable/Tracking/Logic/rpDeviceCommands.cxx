#include "rpDeviceCommands.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "rpArgParser.h"
#include "rpNdiProtocol.h"
#include "rpNdiRom.h"
#include "vtkRPTrackingLogic.h"
#include "rpToolDefinition.h"

namespace rp {

namespace {
nlohmann::json Vectors(const std::vector<rom::Vec3>& v) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& p : v) a.push_back({p[0], p[1], p[2]});
  return a;
}

// Shape facts a user can check against the tool's drawing: segment lengths, and how far the
// markers are from one plane and one line (a 3-marker collinear tool gives 5 DoF only).
nlohmann::json Geometry(const std::vector<rom::Vec3>& markers) {
  nlohmann::json distances = nlohmann::json::array();
  for (size_t i = 0; i < markers.size(); ++i)
    for (size_t j = i + 1; j < markers.size(); ++j) {
      const double d = std::sqrt(std::pow(markers[i][0] - markers[j][0], 2) + std::pow(markers[i][1] - markers[j][1], 2) +
                                 std::pow(markers[i][2] - markers[j][2], 2));
      distances.push_back({{"markers", {i + 1, j + 1}}, {"mm", std::round(d * 1000) / 1000}});
    }
  Eigen::MatrixXd p(static_cast<Eigen::Index>(markers.size()), 3);
  for (size_t i = 0; i < markers.size(); ++i) p.row(static_cast<Eigen::Index>(i)) << markers[i][0], markers[i][1], markers[i][2];
  nlohmann::json doc = {{"segments", distances}};
  if (markers.size() >= 3) {
    const Eigen::RowVector3d centroid = p.colwise().mean();
    const Eigen::MatrixXd centred = p.rowwise() - centroid;
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(centred);
    const auto s = svd.singularValues();
    const double n = std::sqrt(static_cast<double>(markers.size()));
    doc["offPlaneRmsMm"] = s(2) / n;
    doc["offLineRmsMm"] = std::hypot(s(1), s(2)) / n;
    doc["collinear"] = std::hypot(s(1), s(2)) / n < 0.5;
  }
  return doc;
}

nlohmann::json RomJson(const rom::Definition& d, const std::string& path, bool checksumOk) {
  char date[16];
  std::snprintf(date, sizeof date, "%04d-%02d-%02d", d.Year, d.Month, d.Day);
  return {{"file", path},
          {"checksum", d.Checksum},
          {"checksumOk", checksumOk},
          {"manufacturer", d.Manufacturer},
          {"partNumber", d.PartNumber},
          {"toolMainType", d.ToolMainType},
          {"toolSubType", d.ToolSubType},
          {"revision", d.Revision},
          {"sequenceNumber", d.SequenceNumber},
          {"date", date},
          {"markerCount", d.Markers.size()},
          {"minimumMarkers", d.MinimumMarkers},
          {"maxMarkerAngleDeg", d.MaxMarkerAngleDeg},
          {"maxMarkerErrorMm", d.MaxMarkerErrorMm},
          {"markerType", d.MarkerType},
          {"markers", Vectors(d.Markers)},
          {"normals", Vectors(d.Normals)},
          {"faces", d.Faces},
          {"groups", d.Groups},
          {"firingSequence", d.FiringSequence},
          {"faceNormals", Vectors(d.FaceNormals)},
          {"geometry", Geometry(d.Markers)}};
}
}  // namespace

int RunToolInfoCommand(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  ArgParser parser("tool-info", "An NDI tool definition (.rom) or a RoboPlan tool (.json): markers, normals, part number, "
                                "date, checksum verified; --write makes the .rom.");
  parser.Positional("file", "tool definition: .rom or Resources/Tools/*.json")
      .Option("write", "FILE", "write the tool's .rom (from a .json, or a re-written .rom) to FILE");
  if (!parser.Parse(args)) {
    if (parser.HelpRequested()) return out << parser.Usage(), 0;
    return err << parser.Error() << "\n" << parser.Usage(), 2;
  }
  const std::string path = parser.Get("file");
  std::vector<uint8_t> bytes;
  rom::Definition definition;
  std::string error;
  if (!vtkRPTrackingLogic::ReadToolDefinitionFile(path, definition, bytes, error)) {
    err << "roboplan tool-info: " << error << "\n";
    return 1;
  }
  const nlohmann::json doc = RomJson(definition, path, true);
  if (parser.Has("write")) {
    std::ofstream f(parser.Get("write"), std::ios::binary);
    f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!f) return err << "roboplan tool-info: cannot write " << parser.Get("write") << "\n", 1;
  }
  if (parser.Json()) {
    out << doc.dump(2) << "\n";
    return 0;
  }
  out << path << ": " << definition.Manufacturer << " " << definition.PartNumber << " (" << doc["date"].get<std::string>()
      << "), " << definition.Markers.size() << " markers, checksum " << definition.Checksum << " OK\n";
  for (size_t m = 0; m < definition.Markers.size(); ++m) {
    const auto& p = definition.Markers[m];
    const auto& n = definition.Normals[m];
    out << "  marker " << m + 1 << ": (" << p[0] << ", " << p[1] << ", " << p[2] << ") mm, normal (" << n[0] << ", " << n[1]
        << ", " << n[2] << ")\n";
  }
  out << "  segments: " << doc["geometry"]["segments"].dump() << "\n";
  return 0;
}

void AddPlusTrackOptions(ArgParser& parser) {
  parser.Option("plus-config", "FILE", "a PLUS device-set configuration (PlusDeviceSet_*.xml): its NDI tracker, tools, "
                                       "CoordinateDefinitions and PlusOpenIGTLinkServer section")
      .Option("plus-config-dir", "DIR", "PLUS's DeviceSetConfigurationDirectory (where RomFile paths are looked for first)")
      .Option("plus-device", "ID", "with --plus-config: the Id of the NDI tracker to run (default: the first with tools)")
      .Flag("check", "with --plus-config: print what would be set up and what is refused, open no device");
}

namespace {
void PrintCheck(const plus::Configuration& c, const plus::NdiTracker* tracker, const nlohmann::json& served,
                const std::vector<plus::Refusal>& refused, std::ostream& out) {
  out << "PLUS configuration " << c.Source << " (version " << c.Version << "): " << c.Name << "\n";
  if (!tracker) out << "no NDI tracker RoboPlan can run\n";
  for (const plus::NdiTracker& d : c.Trackers) {
    if (&d != tracker) continue;
    out << "tracker " << d.Id << " (" << d.Type << "): ";
    if (d.Tcp()) out << "TCP " << d.NetworkHostname << ":" << d.NetworkPort;
    else if (!d.SerialDevice.empty()) out << "serial " << d.SerialDevice << " (SerialPort " << d.SerialPort << ")";
    else out << "no port in the file: give --serial PORT or --ndi-tcp HOST";
    out << ", tools in frame " << d.ToolReferenceFrame << "\n";
    for (const plus::Tool& t : d.Tools) {
      out << "  tool " << t.Id << " -> " << t.Id << "To" << d.ToolReferenceFrame << ": ";
      if (t.WiredPort >= 0)
        out << ndi::DescribeWiredPort(t.WiredPort) << (t.RomPath.empty() ? " (the SROM in the tool)" : ", virtual SROM " + t.RomPath) << "\n";
      else out << t.RomPath << "\n";
    }
  }
  for (const plus::FixedTransform& t : c.Transforms)
    out << "fixed transform " << t.From << "To" << t.To << (t.Error >= 0 ? " (error " + std::to_string(t.Error) + ")" : "") << "\n";
  const plus::Server& s = c.OpenIGTLinkServer;
  if (s.Present) {
    out << "server: port " << s.ListeningPort << " on " << (s.ListeningAddress.empty() ? "127.0.0.1" : s.ListeningAddress)
        << " (--bind overrides), channel " << s.OutputChannelId << ", "
        << (s.SendValidTransformsOnly ? "valid transforms only" : "invalid transforms too") << ", keep-alive "
        << s.KeepAliveIntervalSec << " s\n";
    for (const auto& t : served) out << "  " << t["name"].get<std::string>() << " = " << t["chain"].get<std::string>() << "\n";
  }
  if (!refused.empty()) {
    out << "refused:\n";
    for (const plus::Refusal& r : refused) out << "  " << r.What << ": " << r.Why << "\n";
  }
}
}  // namespace

int PreparePlusTrack(const ArgParser& parser, PlusTrack& plan, std::ostream& out, std::ostream& err) {
  plus::ResolveOptions options;
  options.DeviceSetConfigurationDirectory = parser.Get("plus-config-dir");
  std::string error;
  if (!plus::ReadConfiguration(parser.Get("plus-config"), options, plan.Configuration, error)) {
    err << "roboplan track: " << error << "\n";
    return 1;
  }
  const plus::Configuration& c = plan.Configuration;
  // One tracker per `roboplan track`: the one named by --plus-device, else the first with tools.
  const plus::NdiTracker* tracker = nullptr;
  std::vector<plus::Refusal> refused = c.Refused;
  const std::string wanted = parser.Get("plus-device");
  if (!wanted.empty()) {
    for (const plus::NdiTracker& d : c.Trackers)
      if (d.Id == wanted && !d.Tools.empty()) tracker = &d;
    if (!tracker) {
      std::string ids;
      for (const plus::NdiTracker& d : c.Trackers)
        if (!d.Tools.empty()) ids += (ids.empty() ? "" : ", ") + d.Id;
      err << "roboplan track: " << c.Source << " has no NDI tracker with Id " << wanted << " and tools to track (it has: "
          << (ids.empty() ? std::string("none") : ids) << ")\n";
      return 2;
    }
  }
  for (const plus::NdiTracker& d : c.Trackers) {
    if (d.Tools.empty() || &d == tracker) continue;
    if (!tracker) tracker = &d;
    else refused.push_back({"Device " + d.Id + " (" + d.Type + ")",
                            "another NDI tracker: run it with a second `roboplan track --plus-device " + d.Id + "`"});
  }
  const nlohmann::json served = ServedTransformsJson(c, tracker, &refused);
  if (parser.Has("check")) {
    if (parser.Json()) {
      nlohmann::json doc = plus::ToJson(c);
      doc["runs"] = tracker ? nlohmann::json(tracker->Id) : nlohmann::json();
      doc["served"] = served;
      doc["refused"] = nlohmann::json::array();
      for (const plus::Refusal& r : refused) doc["refused"].push_back({{"what", r.What}, {"why", r.Why}});
      out << doc.dump(2) << "\n";
    } else {
      PrintCheck(c, tracker, served, refused, out);
    }
    if (!tracker) {  // scripts rely on the exit code: nothing of this file would track
      err << "roboplan track: " << c.Source << " has no NDI tracker RoboPlan can run\n";
      return 1;
    }
    return 0;
  }
  if (!tracker) {
    err << "roboplan track: " << c.Source << " has no NDI tracker RoboPlan can run\n" << c.RefusedMessage() << "\n";
    return 1;
  }
  if (!refused.empty()) {  // one message naming all that is not set up; the rest runs
    err << "track: not set up from " << c.Source << ":";
    for (const plus::Refusal& r : refused) err << "\n  " << r.What << ": " << r.Why;
    err << "\n";
  }
  const bool simulate = parser.Has("simulate");
  std::string address = parser.Has("serial") ? parser.Get("serial") : parser.Get("ndi-tcp");
  plus::NdiTracker device = *tracker;
  if (parser.Has("ndi-tcp")) device.NetworkHostname = "via --ndi-tcp";  // a TCP link, the address given
  if (parser.Has("serial")) device.NetworkHostname.clear();
  try {
    plan.Source = MakePlusPoseSource(device, address, simulate);
  } catch (const std::exception& e) {
    err << "roboplan track: " << e.what() << "\n";
    return 2;
  }
  plan.Config.Kind = simulate ? "simulator" : device.Tcp() ? "tcp" : "serial";
  plan.Config.Address = address.empty() ? (device.Tcp() ? device.NetworkHostname + ":" + std::to_string(device.NetworkPort)
                                                        : device.SerialDevice)
                                        : address;
  plan.Relay = std::make_unique<PlusTransformRelay>(c, *tracker, plan.Source->Poses());
  plan.Commands = std::make_shared<PlusTransformRelay>(c, *tracker, plan.Source->Poses());
  plan.Commands->ForwardUpdatesTo(*plan.Relay);  // UpdateTransform reaches the served transforms
  plan.ServePort = c.OpenIGTLinkServer.Present ? c.OpenIGTLinkServer.ListeningPort : -1;
  plan.ListeningAddress = c.OpenIGTLinkServer.ListeningAddress;
  plan.SendInvalid = !c.OpenIGTLinkServer.SendValidTransformsOnly;
  plan.KeepAliveSeconds = c.OpenIGTLinkServer.KeepAliveIntervalSec;
  return -1;
}

}  // namespace rp
