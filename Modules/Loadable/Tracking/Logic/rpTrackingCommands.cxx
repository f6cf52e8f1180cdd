#include "rpTrackingCommands.h"

#include <poll.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <thread>

#include <nlohmann/json.hpp>
#include <vtkNew.h>

#include "rpArgParser.h"
#include "rpDeviceCommands.h"
#include "rpIgtlServer.h"
#include "rpNetworkAddress.h"
#include "rpNdiProtocol.h"
#include "rpPivotCalibration.h"
#include "rpPolarisSimulator.h"
#include "rpPoseSource.h"
#include "rpProgress.h"
#include "rpToolDefinition.h"
#include "rpTrackingLog.h"
#include "rpTrackingRecording.h"
#include "rpTransformNames.h"
#include "vtkRPScene.h"
#include "vtkRPTrackedToolNode.h"
#include "vtkRPTrackingLogic.h"

namespace rp {

namespace {
std::atomic<bool> gInterrupted{false};
void OnSignal(int) { gInterrupted = true; }

int BadArguments(const ArgParser& parser, std::ostream& err) {
  if (parser.HelpRequested()) {
    err << parser.Usage();
    return 0;
  }
  err << parser.Error() << "\n" << parser.Usage();
  return 2;
}

std::string SourceKindsText() {
  std::string text;
  for (const auto& e : PoseSourceRegistry::Entries())
    text += (text.empty() ? "" : ", ") + e.Kind + (e.AddressHint.empty() ? "" : " (" + e.AddressHint + ")");
  return text;
}

// The configuration from the command line: a kind (--serial/--igtl/--replay/--simulate are
// short for --source KIND --address ...) and the options the user gave (the source's own
// defaults otherwise). Throws std::invalid_argument.
PoseSourceConfig SourceConfig(const ArgParser& parser) {
  PoseSourceConfig config;
  int given = 0;
  for (const char* kind : {"serial", "igtl", "replay"}) {
    if (!parser.Has(kind)) continue;
    ++given;
    config.Kind = kind;
    config.Address = parser.Get(kind);
  }
  if (parser.Has("simulate")) {
    ++given;
    config.Kind = "simulator";
  }
  if (parser.Has("ndi-tcp")) {  // a Polaris Vega/Lyra on Ethernet
    ++given;
    config.Kind = "tcp";
    config.Address = parser.Get("ndi-tcp");
  }
  if (parser.Has("source")) {
    ++given;
    config.Kind = parser.Get("source");
    config.Address = parser.Get("address");
  }
  if (given != 1)
    throw std::invalid_argument("give exactly one of --serial <port>, --ndi-tcp <host[:8765]>, --igtl <host:port>, --replay <file>, "
                                "--simulate, --plus-config <file> or "
                                "--source <kind> (kinds: " + SourceKindsText() + ")");
  config.ToolFiles = parser.GetAll("rom");
  for (const std::string& wired : parser.GetAll("wired"))
    config.Options["wired"] += (config.Options["wired"].empty() ? "" : ",") + wired;
  for (const char* option : {"rate", "header-version", "request", "speed"})
    if (parser.Has(option)) config.Options[option] = parser.Get(option);
  if (parser.Has("text")) config.Options["text"] = "1";
  for (const std::string& pair : parser.GetAll("option")) {
    const size_t eq = pair.find('=');
    if (eq == std::string::npos || eq == 0) throw std::invalid_argument("--option expects KEY=VALUE, got '" + pair + "'");
    config.Options[pair.substr(0, eq)] = pair.substr(eq + 1);
  }
  return config;
}

nlohmann::json PoseJson(const ToolPose& pose) {
  double m[16];
  pose.ToMatrix(m);
  return {{"state", ToolStateName(pose.State)},
          {"matrix", std::vector<double>(m, m + 16)},
          {"position", {pose.Translation[0], pose.Translation[1], pose.Translation[2]}},
          {"quaternion", {pose.Quaternion[0], pose.Quaternion[1], pose.Quaternion[2], pose.Quaternion[3]}},
          {"timestamp", pose.Timestamp}};
}
void DeclareTrackOptions(ArgParser& parser) {
  parser.Option("serial", "PORT", "serial port of an NDI Polaris/Aurora (or a polaris-sim link)")
      .Option("ndi-tcp", "HOST[:PORT]", "NDI Polaris Vega/Lyra over Ethernet (Combined API, port 8765 by default)")
      .Option("igtl", "HOST:PORT", "OpenIGTLink server (e.g. PLUS at 127.0.0.1:18944)")
      .Option("replay", "FILE", "replay a recording (from --record) as if it were a tracker")
      .Flag("simulate", "the built-in simulated Polaris (serial path on a pseudo-terminal)")
      .Option("source", "KIND", "any registered pose source: " + SourceKindsText())
      .Option("address", "ADDRESS", "with --source: port, HOST:PORT or file")
      .Option("option", "KEY=VALUE", "a source option (e.g. noise=0.1); repeatable")
      .Option("rom", "FILE", "tool definition (.rom, or a Resources/Tools .json); repeatable")
      .Option("wired", "NAME=PORT", "serial/ndi-tcp: a wired tool (Aurora sensor, Polaris active tool) in PORT, numbered as "
                                    "PLUS's PortName (0 is port 1; channel * 100 + port - 1)")
          .Repeatable()
      .Option("seconds", "N", "how long to track (a replay ends with its recording)", std::string("5"))
      .Option("record", "FILE", "record every pose to a file (replay, `roboplan pivot`); .igs.mha/.igs.nrrd: a PLUS recording")
      .Option("stale", "S", "seconds without data before a tool is stale", std::string("0.5"))
      .Option("reference", "NAME", "reference tool: also report <Tool>ToReference")
      .Option("rate", "HZ", "serial/simulate: camera frame rate via IRATE (20, 30 or 60) and poll rate")
      .Option("speed", "X", "replay speed factor")
      .Option("serve", "PORT", "also stream the poses as OpenIGTLink TRANSFORMs (PLUS style) on PORT of --bind's address")
      .Option("bind", "ADDRESS", "with --serve: the address to listen on, one of this machine's, or 'all' (every interface; "
                                 "OpenIGTLink has no encryption nor authentication: the lab's network only)",
              std::string("127.0.0.1"))
      .Option("command-clients", "LIST", "with --serve: the addresses or networks (192.168.10.7, 192.168.10.0/24, comma "
                                         "separated; 'none') whose commands may change state or write files (UpdateTransform, "
                                         "StartRecording, StopRecording); others get the stream and read-only commands "
                                         "(default: 127.0.0.0/8, this machine)")
          .Repeatable()
      .Option("record-dir", "DIR", "with --serve: the folder StartRecording writes into (PLUS's OutputDirectory); a client's "
                                   "OutputFilename is a file name in it", std::string("."))
      .Option("log", "FILE", "append the session log (connections, every command with its client and result) to FILE")
      .Option("request", "KIND", "igtl: ask the server to stream 'tdata' or 'qtdata' (STT_)")
      .Option("header-version", "V", "igtl: header version we send: 1, or 2 (v3 framing; PLUS then sends status metadata)")
      .Flag("text", "serial: poll TX (text) instead of BX (binary)");
  AddPlusTrackOptions(parser);
}

// What `roboplan track` was asked to do: the pose source (made, not yet started) and how to run it.
struct TrackRequest {
  PlusTrack Plus;  // --plus-config: the configuration's tracker, transforms and server
  double Seconds = 0, Stale = 0;
  long ServePort = -1;
  std::string Bind;                  // --bind, else the configuration's ListeningAddress, else 127.0.0.1
  AddressAllowList CommandClients = AddressAllowList::Loopback();
  std::string RecordFolder;
  std::shared_ptr<TrackingLog> Log = std::make_shared<TrackingLog>();
  PoseSourceConfig Config;
  std::unique_ptr<PoseSource> Source;
  bool Json = false;
  std::optional<std::string> Reference, RecordPath;  // unset: not given
};

// --bind, --command-clients, --record-dir, --log (the served port's network and its session log).
// Throws std::invalid_argument naming the bad value.
void ReadServeOptions(const ArgParser& parser, TrackRequest& request) {
  request.Bind = parser.Has("bind") || request.Plus.ListeningAddress.empty() ? parser.Get("bind") : request.Plus.ListeningAddress;
  Ipv4 address = 0;
  std::string error;
  if (!ParseBindAddress(request.Bind, address, error)) throw std::invalid_argument("--bind: " + error);
  if (parser.Has("command-clients")) {
    request.CommandClients = AddressAllowList();
    for (const std::string& list : parser.GetAll("command-clients"))
      if (!request.CommandClients.Add(list, error)) throw std::invalid_argument("--command-clients: " + error);
  }
  request.RecordFolder = parser.Get("record-dir");
  if (parser.Has("log") && !request.Log->Open(parser.Get("log"), error)) throw std::runtime_error(error);
}

// Options -> request; -1 to go on tracking, otherwise the exit code (--check done, or an error printed).
int ReadTrackRequest(const ArgParser& parser, TrackRequest& request, std::ostream& out, std::ostream& err) {
  try {
    request.Seconds = parser.GetDouble("seconds");
    request.Stale = parser.GetDouble("stale");
    if (parser.Has("serve")) request.ServePort = parser.GetInt("serve");
    if (parser.Has("plus-config")) {
      const int code = PreparePlusTrack(parser, request.Plus, out, err);
      if (code >= 0) return code;
      request.Config = request.Plus.Config;
      request.Source = std::move(request.Plus.Source);
      if (request.ServePort < 0) request.ServePort = request.Plus.ServePort;
    } else {
      request.Config = SourceConfig(parser);
      request.Source = PoseSourceRegistry::Create(request.Config);
    }
    ReadServeOptions(parser, request);
  } catch (const std::invalid_argument& e) {
    err << "roboplan track: " << e.what() << "\n" << parser.Usage();
    return 2;
  } catch (const std::exception& e) {
    err << "roboplan track: " << e.what() << "\n";
    return 1;
  }
  request.Json = parser.Json();
  if (parser.Has("reference")) request.Reference = parser.Get("reference");
  if (parser.Has("record")) request.RecordPath = parser.Get("record");
  return -1;
}

// The OpenIGTLink server of --serve (PLUS's served names and settings with --plus-config); null on failure.
std::unique_ptr<IgtlServer> StartTrackServer(const TrackRequest& request, const ToolPoseTable& table, std::string& error) {
  const PlusTrack& plus = request.Plus;
  IgtlServer::Options so;
  so.Port = static_cast<int>(request.ServePort);
  so.BindAddress = request.Bind;
  so.CommandClients = request.CommandClients;
  so.RecordFolder = request.RecordFolder;
  std::shared_ptr<TrackingLog> log = request.Log;
  so.Log = [log](const std::string& line) { log->Add(line); };
  if (plus.Relay) {  // PLUS's served names (chains through its transforms), its send and keep-alive settings
    so.SendInvalid = plus.SendInvalid;
    so.KeepAliveSeconds = plus.KeepAliveSeconds;
    // GetTransform/UpdateTransform act on the configuration's transform repository, as in PLUS
    std::shared_ptr<PlusTransformRelay> repository = plus.Commands;
    so.Transforms = [repository](const std::string& from, const std::string& to, double m[16], ToolState& state) {
      return repository->Get(from, to, m, state);
    };
    so.UpdateTransforms = [repository](const std::string& from, const std::string& to, const double m[16], std::string& e) {
      return repository->Set(from, to, m, e);
    };
  }
  auto server = std::make_unique<IgtlServer>(plus.Relay ? plus.Relay->Output() : table, so);
  if (!server->Start(error)) return nullptr;
  return server;
}

// Tracks until the request's seconds pass, the source finishes (a replay) or SIGINT; nodes follow the
// source, poses go to `recorder` when it is open. Returns the seconds tracked.
double TrackUntilDone(vtkRPTrackingLogic* logic, PoseSource* tracker, const TrackRequest& request, RecordingWriter* recorder,
                      std::ostream& err) {
  const ToolPoseTable& table = tracker->Poses();
  ToolPoseReader recordReader;
  PlusTransformRelay* relay = request.Plus.Relay.get();
  const double seconds = request.Seconds;
  gInterrupted = false;
  auto previousInt = std::signal(SIGINT, OnSignal);
  TerminalProgress progress("track", request.Json, err);
  const double start = SteadySeconds();
  double nextReport = start;
  std::vector<pollfd> ready;
  for (int fd : logic->GetReadyFds()) ready.push_back({fd, POLLIN, 0});
  while (!gInterrupted) {
    const double now = SteadySeconds();
    if (now - start >= seconds || tracker->Finished()) break;  // a replay ends with its recording
    // Nodes follow the source as soon as it publishes (and at least every 16 ms, for staleness).
    ::poll(ready.data(), ready.size(), static_cast<int>(std::min(16.0, 1e3 * (start + seconds - now))) + 1);
    if (recorder) {
      for (int i = 0; i < table.Count(); ++i) {
        const auto& s = recordReader.Poll(table, i);
        if (s.Fresh) recorder->Add(table.Name(i), s.Pose.ReceiveTime - start, s.Pose);
      }
    }
    if (relay) relay->Update();
    logic->UpdateNodes(SteadySeconds());
    request.Log->Echo(err);  // the server's connections and commands, as they happen
    if (SteadySeconds() >= nextReport) {
      nextReport += 0.25;
      std::string status = tracker->StatusText();
      for (const auto& t : logic->GetToolStatistics())
        status += " | " + t.NodeName + " " + vtkRPTrackedToolNode::GetStatusAsString(t.Status);
      progress.Report((SteadySeconds() - start) / seconds, status);
    }
  }
  std::signal(SIGINT, previousInt);
  logic->UpdateNodes(SteadySeconds());
  return SteadySeconds() - start;
}

// The run's results as the --json document (the text report is read from it too); counts what arrived.
nlohmann::json TrackResults(vtkRPTrackingLogic* logic, PoseSource* tracker, const TrackRequest& request,
                            IgtlServer* server, double elapsed, uint64_t& withPose, uint64_t& images) {
  nlohmann::json doc;
  doc["seconds"] = elapsed;
  doc["source"] = request.Config.Kind;
  doc["address"] = request.Config.Address;
  doc["status"] = tracker->StatusText();
  doc["device"] = tracker->StatisticsJson();
  if (server) {
    const auto s = server->GetStatistics();
    doc["served"] = {{"port", server->Port()}, {"messagesSent", s.MessagesSent}, {"clientsAccepted", s.Accepted},
                     {"clientsRefused", s.Refused}, {"messagesDropped", s.MessagesDropped}};
  }
  if (request.Plus.Relay) {  // the PLUS transforms as served: newest status of each
    const ToolPoseTable& served = request.Plus.Relay->Output();
    for (int i = 0; i < served.Count(); ++i) {
      ToolPose pose;
      const uint64_t n = served.Read(i, pose);
      doc["plusTransforms"].push_back({{"name", served.Name(i)}, {"published", n}, {"state", n ? ToolStateName(pose.State) : "NONE"},
                                       {"position", {pose.Translation[0], pose.Translation[1], pose.Translation[2]}}});
    }
  }
  doc["tools"] = nlohmann::json::array();
  withPose = 0;
  for (const auto& t : logic->GetToolStatistics()) {
    withPose += t.Frames.WithPose();
    nlohmann::json tool = {
        {"name", t.NodeName},
        {"status", vtkRPTrackedToolNode::GetStatusAsString(t.Status)},
        {"frames", {{"ok", t.Frames.Ok}, {"missing", t.Frames.Missing}, {"outOfVolume", t.Frames.OutOfVolume},
                    {"disabled", t.Frames.Disabled}}},
        {"received", t.Frames.WithPose()},  // frames that carry a pose (OK, out of volume)
        {"dropped", t.Dropped},
        {"rateHz", elapsed > 0 ? static_cast<double>(t.Frames.WithPose()) / elapsed : 0.0},
        {"latencyMs", t.LatencySeconds * 1e3},
        {"meanLatencyMs", t.MeanLatencySeconds * 1e3},
        {"maxLatencyMs", t.MaxLatencySeconds * 1e3},
        {"errorRmsMm", t.ErrorRMS}};
    tool["lastPose"] = t.HasPose ? PoseJson(t.LastPose) : nlohmann::json();
    doc["tools"].push_back(tool);
  }
  doc["images"] = nlohmann::json::array();
  images = 0;
  for (const auto& i : logic->GetImageStatistics()) {
    images += i.Frames;
    doc["images"].push_back({{"name", i.NodeName}, {"frames", i.Frames}, {"shown", i.Shown},
                             {"dimensions", {i.Dimensions[0], i.Dimensions[1], i.Dimensions[2]}},
                             {"latencyMs", i.LatencySeconds * 1e3}});
  }
  return doc;
}

void ReportTrackText(const nlohmann::json& doc, const PoseSourceConfig& config, double elapsed, std::ostream& out) {
  out << "source: " << config.Kind << " " << config.Address << ", " << elapsed << " s: " << doc["status"].get<std::string>() << "\n";
  out << "device: " << doc["device"].dump() << "\n";
  for (const auto& t : doc["tools"]) {
    out << "  " << t["name"].get<std::string>() << ": " << t["status"].get<std::string>() << ", "
        << t["rateHz"].get<double>() << " Hz, latency " << t["latencyMs"].get<double>() << " ms; frames OK "
        << t["frames"]["ok"].get<uint64_t>() << ", missing " << t["frames"]["missing"].get<uint64_t>()
        << ", out of volume " << t["frames"]["outOfVolume"].get<uint64_t>() << ", dropped " << t["dropped"].get<uint64_t>();
    if (!t["lastPose"].is_null()) {
      const auto& p = t["lastPose"]["position"];
      out << "; last at (" << p[0].get<double>() << ", " << p[1].get<double>() << ", " << p[2].get<double>() << ") mm";
    }
    out << "\n";
  }
  for (const auto& i : doc["images"])
    out << "  image " << i["name"].get<std::string>() << ": " << i["frames"].get<uint64_t>() << " frames "
        << i["dimensions"].dump() << "\n";
}
}  // namespace

int RunTrackCommand(const std::vector<std::string>& args, vtkRPScene* scene, std::ostream& out, std::ostream& err) {
  ArgParser parser("track", "Track tools from a pose source (an NDI tracker, an OpenIGTLink server, a recording, the "
                            "simulator); print per tool the last pose, OK/MISSING/out-of-volume frames, rate and latency.");
  DeclareTrackOptions(parser);
  if (!parser.Parse(args)) return BadArguments(parser, err);
  TrackRequest request;
  if (const int code = ReadTrackRequest(parser, request, out, err); code >= 0) return code;

  vtkNew<vtkRPScene> ownScene;
  vtkNew<vtkRPTrackingLogic> logic;
  logic->SetScene(scene ? scene : ownScene.Get());
  logic->SetStaleTimeout(request.Stale);
  if (request.Reference) logic->SetReferenceNodeName(ToolToTrackerName(*request.Reference));
  std::string error;
  const int sourceId = logic->AddSource(std::move(request.Source), error);
  if (sourceId < 0) {
    err << "roboplan track: " << error << "\n";
    return 1;
  }
  PoseSource* tracker = logic->GetSource(sourceId);
  std::unique_ptr<IgtlServer> server;
  if (request.ServePort >= 0) {
    server = StartTrackServer(request, tracker->Poses(), error);
    if (!server) {
      err << "roboplan track: " << error << "\n";
      return 1;
    }
    request.Log->Echo(err);  // "serving OpenIGTLink on ..."
    Ipv4 bound = 0;
    std::string ignored;
    if (ParseBindAddress(request.Bind, bound, ignored) && !IsLoopback(bound))
      err << "track: warning: other machines can reach this port; OpenIGTLink has no encryption nor authentication: keep it "
             "on the lab's network (commands that change state or write files: " << request.CommandClients.ToString() << " only)\n";
  }
  RecordingWriter recorder;
  const bool record = request.RecordPath.has_value();
  if (record && !recorder.Open(*request.RecordPath, error)) {
    err << "roboplan track: " << error << "\n";
    return 1;
  }
  const double elapsed = TrackUntilDone(logic, tracker, request, record ? &recorder : nullptr, err);
  if (!recorder.Close(&error)) {
    err << "roboplan track: " << error << "\n";
    return 1;
  }

  uint64_t withPose = 0, images = 0;
  nlohmann::json doc = TrackResults(logic, tracker, request, server.get(), elapsed, withPose, images);
  if (record) doc["recorded"] = recorder.Count();
  if (server) server->Stop();
  request.Log->Echo(err);
  logic->RemoveSource(sourceId);  // stops the device (TSTOP, PHF, COMM 9600 ...)
  if (request.Json)
    out << doc.dump(2) << "\n";
  else
    ReportTrackText(doc, request.Config, elapsed, out);
  if (withPose == 0 && images == 0) {
    const std::string lastError = doc["device"].value("lastError", std::string());
    err << "roboplan track: no poses received" << (lastError.empty() ? "" : ": " + lastError) << "\n";
    return 1;
  }
  return 0;
}

int RunPivotCommand(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  ArgParser parser("pivot", "Pivot calibration of a stylus tip (StylusTipToStylus) from a tracking recording.");
  parser.Positional("recording", "file written by `roboplan track --record`")
      .Option("tool", "NAME", "stylus tool name (default: the first containing 'Stylus')")
      .Option("reference", "NAME", "calibrate relative to this reference tool (ToolToReference)")
      .Option("threshold", "MM", "reject the calibration above this RMSE", std::string("1.0"));
  if (!parser.Parse(args)) return BadArguments(parser, err);
  double threshold;
  try {
    threshold = parser.GetDouble("threshold");
  } catch (const std::exception& e) {
    err << "roboplan pivot: " << e.what() << "\n";
    return 2;
  }
  Recording recording;
  try {
    recording = Recording::Read(parser.Get("recording"));
  } catch (const std::exception& e) {
    err << "roboplan pivot: " << e.what() << "\n";
    return 1;
  }
  std::string tool = parser.Get("tool");
  if (tool.empty()) {
    for (const auto& name : recording.Tools)
      if (name.find("Stylus") != std::string::npos) {
        tool = name;
        break;
      }
    if (tool.empty() && !recording.Tools.empty()) tool = recording.Tools.front();
  }
  // A tool is named as recorded: "Stylus" (serial) or "StylusToTracker" (OpenIGTLink); either works.
  auto indexOf = [&](const std::string& name) {
    const int index = recording.ToolIndex(name);
    return index >= 0 ? index : recording.ToolIndex(ToolToTrackerName(name));
  };
  if (indexOf(tool) < 0) {
    err << "roboplan pivot: no tool '" << tool << "' in " << parser.Get("recording") << "\n";
    return 1;
  }
  std::vector<ToolPose> poses;
  if (parser.Has("reference")) {
    // Pair each tool pose with the newest reference pose recorded before it.
    const int toolIndex = indexOf(tool), refIndex = indexOf(parser.Get("reference"));
    if (refIndex < 0) {
      err << "roboplan pivot: no reference tool '" << parser.Get("reference") << "' in the recording\n";
      return 1;
    }
    ToolPose reference;
    bool haveReference = false;
    for (const auto& s : recording.Samples) {
      if (s.Tool == refIndex) {
        reference = s.Pose;
        haveReference = true;
      } else if (s.Tool == toolIndex && haveReference) {
        poses.push_back(ToolToReference(s.Pose, reference));
      }
    }
  } else {
    poses = recording.PosesOf(recording.Tools[static_cast<size_t>(indexOf(tool))]);
  }
  vtkNew<vtkRPTrackingLogic> logic;  // no scene: the command reports the calibration, applies none
  const PivotResult r = logic->CalibratePivot(poses, tool, threshold);
  nlohmann::json doc = {{"tool", tool},
                        {"valid", r.Valid},
                        {"accepted", r.Accepted},
                        {"posesUsed", r.PosesUsed},
                        {"tipOffsetMm", r.TipOffset},
                        {"pivotPointMm", r.PivotPoint},
                        {"rmseMm", r.Rmse},
                        {"maxErrorMm", r.MaxError},
                        {"rotationSpreadDeg", r.RotationSpreadDeg},
                        {"thresholdMm", threshold},
                        {"message", r.Message}};
  if (parser.Json()) {
    out << doc.dump(2) << "\n";
  } else {
    out << "StylusTipToStylus (" << tool << "): " << r.TipOffset[0] << " " << r.TipOffset[1] << " " << r.TipOffset[2]
        << " mm\npivot point: " << r.PivotPoint[0] << " " << r.PivotPoint[1] << " " << r.PivotPoint[2] << " mm\nRMSE "
        << r.Rmse << " mm (max " << r.MaxError << "), " << r.PosesUsed << " poses, rotation spread "
        << r.RotationSpreadDeg << " deg: " << (r.Accepted ? "accepted" : "REJECTED") << "\n";
  }
  if (!r.Accepted) {
    err << "roboplan pivot: " << r.Message << "\n";
    return 1;
  }
  return 0;
}

int RunPolarisSimCommand(const std::vector<std::string>& args, std::ostream& out, std::ostream& err, const std::atomic<bool>* stop) {
  ArgParser parser("polaris-sim", "A simulated NDI Polaris on a pseudo-terminal, or over TCP as a Polaris Vega: prints the "
                                  "port to open.");
  parser.Option("port-link", "PATH", "symlink to the pty (kept across replug); breaks arrive on PATH.break")
      .Option("tcp", "PORT", "serve the Combined API over TCP on 127.0.0.1:PORT (a Vega/Lyra; 0: any free port)")
      .Option("tool", "FILE", "tool definition .json or NDI .rom (default: every Resources/Tools/*.json); repeatable")
      .Option("wired", "PORT=FILE", "a tool (.json or .rom: the SROM in it) plugged into wired PORT, numbered as PLUS's "
                                    "PortName (0 is port 1)")
          .Repeatable()
      .Option("rate", "HZ", "frame rate: 20 (Vicra) or 60 (Spectra)", std::string("60"))
      .Option("noise", "MM", "translation noise (standard deviation)", std::string("0.05"))
      .Option("noise-deg", "DEG", "rotation noise (standard deviation)", std::string("0.02"))
      .Option("seconds", "N", "stop after N seconds (default: until interrupted)")
      .Option("export-roms", "DIR", "write the tools' .rom files to DIR and exit");
  if (!parser.Parse(args)) return BadArguments(parser, err);
  PolarisSimulator::Options o;
  double seconds = -1;
  try {
    o.FrameRate = parser.GetDouble("rate");
    o.NoiseMm = parser.GetDouble("noise");
    o.NoiseDeg = parser.GetDouble("noise-deg");
    if (parser.Has("seconds")) seconds = parser.GetDouble("seconds");
    if (parser.Has("tcp")) o.TcpPort = static_cast<int>(parser.GetInt("tcp"));
  } catch (const std::exception& e) {
    err << "roboplan polaris-sim: " << e.what() << "\n";
    return 2;
  }
  if (o.FrameRate != 20 && o.FrameRate != 30 && o.FrameRate != 60) {
    err << "roboplan polaris-sim: --rate must be 20, 30 or 60\n";
    return 2;
  }
  o.LinkPath = parser.Get("port-link");
  std::vector<std::string> files = parser.GetAll("tool");
  const std::vector<std::string> wired = parser.GetAll("wired");
  if (files.empty() && wired.empty()) files = DefaultToolFiles();
  std::vector<ToolDefinition> tools;
  std::vector<int> ports;  // -1: a passive tool, else its wired port (PLUS's PortName numbering)
  try {
    for (const auto& f : files) tools.push_back(ReadToolFile(f));  // a .rom: its markers, standing still
    ports.assign(tools.size(), -1);
    for (const std::string& item : wired) {
      const size_t equals = item.find('=');
      int port = -1;
      if (equals == std::string::npos || !ndi::ParseWiredPort(item.substr(0, equals), port))
        throw std::invalid_argument("--wired '" + item + "': give PORT=FILE, PORT 0 for port 1 (as PLUS's PortName)");
      tools.push_back(ReadToolFile(item.substr(equals + 1)));
      ports.push_back(port);
    }
  } catch (const std::exception& e) {
    err << "roboplan polaris-sim: " << e.what() << "\n";
    return 1;
  }
  if (parser.Has("export-roms")) {
    const std::string dir = parser.Get("export-roms");
    std::filesystem::create_directories(dir);
    for (const auto& t : tools) {
      std::ofstream f(dir + "/" + t.Name + ".rom", std::ios::binary);
      f.write(reinterpret_cast<const char*>(t.Rom.data()), static_cast<std::streamsize>(t.Rom.size()));
      if (!f) {
        err << "roboplan polaris-sim: cannot write " << dir << "/" << t.Name << ".rom\n";
        return 1;
      }
      out << dir << "/" << t.Name << ".rom\n";
    }
    return 0;
  }
  std::string error;
  const std::unique_ptr<PolarisSimulator> simulator = vtkRPTrackingLogic::StartSimulatedPolaris(o, tools, ports, error);
  if (!simulator) {
    err << "roboplan polaris-sim: " << error << "\n";
    return 1;
  }
  PolarisSimulator& sim = *simulator;
  if (parser.Json()) {
    nlohmann::json doc = {{"port", sim.PortPath()}, {"pty", sim.SlavePath()}, {"rateHz", o.FrameRate}};
    for (const auto& t : tools) doc["tools"].push_back(t.Name);
    out << doc.dump() << std::endl;
  } else {
    out << sim.PortPath() << std::endl;  // first line: the port to open
    err << "polaris-sim: " << tools.size() << " tools at " << o.FrameRate << " Hz on " << sim.SlavePath()
        << "; try: roboplan track " << (sim.Tcp() ? "--ndi-tcp " : "--serial ") << sim.PortPath()
        << " --rom <Resources/Tools/Stylus.json>\n";
  }
  gInterrupted = false;
  auto previousInt = std::signal(SIGINT, OnSignal);
  auto previousTerm = std::signal(SIGTERM, OnSignal);
  const double start = SteadySeconds();
  while (!gInterrupted && !(stop && *stop) && (seconds < 0 || SteadySeconds() - start < seconds))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  std::signal(SIGINT, previousInt);
  std::signal(SIGTERM, previousTerm);
  sim.Stop();
  return 0;
}

}  // namespace rp
