#include "rpTrackingCommands.h"

#include <csignal>
#include <filesystem>
#include <fstream>
#include <memory>
#include <thread>

#include <nlohmann/json.hpp>
#include <vtkNew.h>

#include "rpArgParser.h"
#include "rpIgtlClient.h"
#include "rpIgtlServer.h"
#include "rpNdiTracker.h"
#include "rpPivotCalibration.h"
#include "rpPolarisSimulator.h"
#include "rpProgress.h"
#include "rpToolDefinition.h"
#include "rpTrackingRecording.h"
#include "rpTransformNames.h"
#include "vtkRPScene.h"
#include "vtkRPTrackedToolNode.h"
#include "vtkRPTrackingLogic.h"

#ifndef ROBOPLAN_RESOURCES_DIR
#define ROBOPLAN_RESOURCES_DIR ""
#endif

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

// A --rom argument: an NDI .rom file (tool named after the file) or a tool definition .json.
NdiTracker::Tool LoadTool(const std::string& path) {
  NdiTracker::Tool tool;
  if (std::filesystem::path(path).extension() == ".json") {
    const ToolDefinition d = ReadToolDefinition(path);
    tool.Name = d.Name;
    tool.Rom = d.Rom;
  } else {
    tool.Name = std::filesystem::path(path).stem().string();
    tool.Rom = ReadBinaryFile(path);
  }
  return tool;
}

std::vector<std::string> DefaultToolFiles() {
  std::vector<std::string> files;
  const std::string dir = std::string(ROBOPLAN_RESOURCES_DIR) + "/Tools";
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec))
    if (entry.path().extension() == ".json") files.push_back(entry.path().string());
  std::sort(files.begin(), files.end());
  return files;
}
}  // namespace

int RunTrackCommand(const std::vector<std::string>& args, vtkRPScene* scene, std::ostream& out, std::ostream& err) {
  ArgParser parser("track", "Track tools through a serial NDI link or OpenIGTLink; print rate, latency and status per tool.");
  parser.Option("serial", "PORT", "serial port of an NDI Polaris (or a polaris-sim link)")
      .Option("igtl", "HOST:PORT", "OpenIGTLink server (e.g. PLUS at 127.0.0.1:18944)")
      .Option("replay", "FILE", "replay a recording (from --record) as if it were a tracker")
      .Option("speed", "X", "replay speed factor", std::string("1"))
      .Option("rom", "FILE", "passive tool definition (.rom, or a Resources/Tools .json); repeatable")
      .Option("seconds", "N", "how long to track", std::string("5"))
      .Option("record", "FILE", "record every pose to a file (replay, `roboplan pivot`)")
      .Option("stale", "S", "seconds without data before a tool is stale", std::string("0.5"))
      .Option("reference", "NAME", "reference tool: also report <Tool>ToReference")
      .Option("rate", "HZ", "serial: camera frame rate via IRATE (20, 30 or 60) and poll rate", std::string("60"))
      .Option("serve", "PORT", "also stream the poses as OpenIGTLink TRANSFORMs (PLUS style) on 127.0.0.1:PORT")
      .Option("request", "KIND", "igtl: ask the server to stream 'tdata' or 'qtdata' (STT_)")
      .Option("header-version", "V", "igtl: header version we send: 1, or 2 (v3 framing; PLUS then sends status metadata)",
              std::string("1"))
      .Flag("text", "serial: poll TX (text) instead of BX (binary)");
  if (!parser.Parse(args)) return BadArguments(parser, err);
  if (int(parser.Has("serial")) + int(parser.Has("igtl")) + int(parser.Has("replay")) != 1) {
    err << "roboplan track: give exactly one of --serial <port>, --igtl <host:port> or --replay <file>\n" << parser.Usage();
    return 2;
  }
  double seconds, stale, rate;
  long headerVersion, servePort = -1;
  try {
    seconds = parser.GetDouble("seconds");
    stale = parser.GetDouble("stale");
    rate = parser.GetDouble("rate");
    headerVersion = parser.GetInt("header-version");
    if (parser.Has("serve")) servePort = parser.GetInt("serve");
  } catch (const std::exception& e) {
    err << "roboplan track: " << e.what() << "\n";
    return 2;
  }
  if (rate != 20 && rate != 30 && rate != 60) {
    err << "roboplan track: --rate must be 20, 30 or 60\n";
    return 2;
  }
  if (headerVersion != 1 && headerVersion != 2) {
    err << "roboplan track: --header-version must be 1 or 2\n";
    return 2;
  }
  const std::string request = parser.Get("request");
  if (!request.empty() && request != "tdata" && request != "qtdata") {
    err << "roboplan track: --request must be tdata or qtdata\n";
    return 2;
  }
  const bool json = parser.Json();
  std::unique_ptr<NdiTracker> serial;
  std::unique_ptr<IgtlClient> igtlClient;
  std::unique_ptr<Recording> replayed;
  std::unique_ptr<RecordingPlayer> player;
  const ToolPoseTable* table = nullptr;
  if (parser.Has("serial")) {
    NdiTracker::Options o;
    o.Port = parser.Get("serial");
    o.Binary = !parser.Has("text");
    o.PollHz = rate;
    o.RateCode = rate == 20 ? 0 : rate == 30 ? 1 : 2;
    std::vector<std::string> roms = parser.GetAll("rom");
    if (roms.empty()) {
      err << "roboplan track: --serial needs at least one --rom <file> (tool definitions to load)\n";
      return 2;
    }
    for (const std::string& rom : roms) {
      try {
        o.Tools.push_back(LoadTool(rom));
      } catch (const std::exception& e) {
        err << "roboplan track: " << e.what() << "\n";
        return 1;
      }
    }
    serial = std::make_unique<NdiTracker>(o);
    table = &serial->Poses();
    serial->Start();
  } else if (parser.Has("replay")) {
    double speed;
    try {
      speed = parser.GetDouble("speed");
      replayed = std::make_unique<Recording>(Recording::Read(parser.Get("replay")));
    } catch (const std::invalid_argument& e) {
      err << "roboplan track: " << e.what() << "\n";
      return 2;
    } catch (const std::exception& e) {
      err << "roboplan track: " << e.what() << "\n";
      return 1;
    }
    player = std::make_unique<RecordingPlayer>(*replayed, speed);
    table = &player->Poses();
    player->Start();
  } else {
    const std::string target = parser.Get("igtl");
    const size_t colon = target.rfind(':');
    IgtlClient::Options o;
    try {
      if (colon == std::string::npos) throw std::invalid_argument("no port");
      o.Host = target.substr(0, colon);
      o.Port = std::stoi(target.substr(colon + 1));
      if (o.Port <= 0 || o.Port > 65535) throw std::invalid_argument("port out of range");
    } catch (const std::exception&) {
      err << "roboplan track: --igtl expects HOST:PORT, got '" << target << "'\n";
      return 2;
    }
    o.HeaderVersion = static_cast<uint16_t>(headerVersion);
    o.RequestTrackingData = request == "tdata";
    o.RequestQuaternionData = request == "qtdata";
    igtlClient = std::make_unique<IgtlClient>(o);
    table = &igtlClient->Poses();
    igtlClient->Start();
  }

  std::unique_ptr<IgtlServer> server;
  if (servePort >= 0) {
    IgtlServer::Options so;
    so.Port = static_cast<int>(servePort);
    server = std::make_unique<IgtlServer>(*table, so);
    std::string error;
    if (!server->Start(error)) {
      err << "roboplan track: " << error << "\n";
      return 1;
    }
    err << "track: serving OpenIGTLink on 127.0.0.1:" << server->Port() << "\n";
  }

  vtkNew<vtkRPScene> ownScene;
  vtkRPScene* target = scene ? scene : ownScene.Get();
  vtkNew<vtkRPTrackingLogic> logic;
  logic->SetScene(target);
  logic->SetStaleTimeout(stale);
  logic->AddPoseSource(table);
  if (parser.Has("reference")) logic->SetReferenceNodeName(ToolToTrackerName(parser.Get("reference")));

  RecordingWriter recorder;
  ToolPoseReader recordReader;
  if (parser.Has("record")) {
    std::string error;
    if (!recorder.Open(parser.Get("record"), error)) {
      err << "roboplan track: " << error << "\n";
      return 1;
    }
  }
  gInterrupted = false;
  auto previousInt = std::signal(SIGINT, OnSignal);
  TerminalProgress progress("track", json);
  const double start = SteadySeconds();
  int tick = 0;
  while (!gInterrupted) {
    const double now = SteadySeconds();
    if (now - start >= seconds) break;
    // Record every pose (polled at 250 Hz, faster than any tracker), update nodes at ~60 Hz.
    if (recorder.Count() || parser.Has("record")) {
      for (int i = 0; i < table->Count(); ++i) {
        const auto& s = recordReader.Poll(*table, i);
        if (s.Fresh) recorder.Add(table->Name(i), s.Pose.ReceiveTime - start, s.Pose);
      }
    }
    if (tick++ % 4 == 0) {
      logic->UpdateNodes(now);
      std::string status = serial ? NdiTracker::StateName(serial->GetState())
                           : player ? (player->Finished() ? "replay finished" : "replaying")
                                    : (igtlClient->Connected() ? "connected" : "connecting");
      for (const auto& t : logic->GetToolStatistics())
        status += " | " + t.NodeName + " " + vtkRPTrackedToolNode::GetStatusAsString(t.Status);
      progress.Report((now - start) / seconds, status);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(4));
  }
  std::signal(SIGINT, previousInt);
  logic->UpdateNodes(SteadySeconds());
  const double elapsed = SteadySeconds() - start;
  recorder.Close();

  nlohmann::json doc;
  doc["seconds"] = elapsed;
  doc["source"] = serial ? "serial" : player ? "replay" : "igtl";
  std::string lastError;
  if (serial) {
    const auto s = serial->GetStatistics();
    doc["device"] = {{"state", NdiTracker::StateName(serial->GetState())}, {"firmware", serial->FirmwareVersion()},
                     {"baud", serial->NegotiatedBaud()}, {"frames", s.Frames}, {"crcErrors", s.CrcErrors},
                     {"timeouts", s.Timeouts}, {"frameGaps", s.FrameGaps}, {"deviceErrors", s.DeviceErrors},
                     {"connections", s.Connections}, {"resets", s.Resets}};
    lastError = serial->LastError();
    serial->Stop();
  } else if (player) {
    doc["device"] = {{"recording", parser.Get("replay")}, {"samples", replayed->Samples.size()}, {"finished", player->Finished()}};
    player->Stop();
  } else {
    const auto s = igtlClient->GetStatistics();
    doc["device"] = {{"connected", igtlClient->Connected()}, {"messages", s.Messages}, {"crcErrors", s.CrcErrors},
                     {"malformed", s.Malformed}, {"oversized", s.Oversized}, {"skipped", s.Skipped},
                     {"connections", s.Connections}, {"keepAlivesSent", s.KeepAlivesSent}};
    lastError = igtlClient->LastError();
    igtlClient->Stop();
  }
  doc["lastError"] = lastError;
  if (server) {
    doc["served"] = {{"port", server->Port()}, {"messagesSent", server->MessagesSent()}};
    server->Stop();
  }
  doc["tools"] = nlohmann::json::array();
  uint64_t total = 0;
  for (const auto& t : logic->GetToolStatistics()) {
    total += t.Received;
    doc["tools"].push_back({{"name", t.NodeName}, {"status", vtkRPTrackedToolNode::GetStatusAsString(t.Status)},
                            {"received", t.Received}, {"dropped", t.Dropped},
                            {"rateHz", elapsed > 0 ? static_cast<double>(t.Received) / elapsed : 0.0},
                            {"latencyMs", t.LatencySeconds * 1e3}, {"errorRmsMm", t.ErrorRMS}});
  }
  if (parser.Has("record")) doc["recorded"] = recorder.Count();
  if (json) {
    out << doc.dump(2) << "\n";
  } else {
    out << "source: " << doc["source"].get<std::string>() << ", " << elapsed << " s\n";
    out << "device: " << doc["device"].dump() << "\n";
    for (const auto& t : doc["tools"])
      out << "  " << t["name"].get<std::string>() << ": " << t["status"].get<std::string>() << ", "
          << t["rateHz"].get<double>() << " Hz, latency " << t["latencyMs"].get<double>() << " ms, received "
          << t["received"].get<uint64_t>() << ", dropped " << t["dropped"].get<uint64_t>() << "\n";
  }
  if (total == 0) {
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
  if (recording.ToolIndex(tool) < 0) {
    err << "roboplan pivot: no tool '" << tool << "' in " << parser.Get("recording") << "\n";
    return 1;
  }
  std::vector<ToolPose> poses;
  if (parser.Has("reference")) {
    // Pair each tool pose with the newest reference pose recorded before it.
    const int toolIndex = recording.ToolIndex(tool), refIndex = recording.ToolIndex(parser.Get("reference"));
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
    poses = recording.PosesOf(tool);
  }
  const PivotResult r = PivotCalibrate(poses, threshold);
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
  ArgParser parser("polaris-sim", "A simulated NDI Polaris on a pseudo-terminal: prints the port to open.");
  parser.Option("port-link", "PATH", "symlink to the pty (kept across replug); breaks arrive on PATH.break")
      .Option("tool", "FILE", "tool definition .json (default: every Resources/Tools/*.json); repeatable")
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
  if (files.empty()) files = DefaultToolFiles();
  std::vector<ToolDefinition> tools;
  try {
    for (const auto& f : files) tools.push_back(ReadToolDefinition(f));
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
  PolarisSimulator sim(o);
  for (const auto& t : tools) sim.AddTool(t);
  std::string error;
  if (!sim.Start(error)) {
    err << "roboplan polaris-sim: " << error << "\n";
    return 1;
  }
  if (parser.Json()) {
    nlohmann::json doc = {{"port", sim.PortPath()}, {"pty", sim.SlavePath()}, {"rateHz", o.FrameRate}};
    for (const auto& t : tools) doc["tools"].push_back(t.Name);
    out << doc.dump() << std::endl;
  } else {
    out << sim.PortPath() << std::endl;  // first line: the port to open
    err << "polaris-sim: " << tools.size() << " tools at " << o.FrameRate << " Hz on " << sim.SlavePath()
        << "; try: roboplan track --serial " << sim.PortPath() << " --rom <Resources/Tools/Stylus.json>\n";
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
