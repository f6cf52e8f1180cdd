// Scene bridge: poses published by I/O threads land in tracked-tool nodes in one batch, tools go
// stale, ToolToReference nodes, dropped counts, deleting a node that receives data, and the
// whole chain simulator → serial driver → scene and driver → OpenIGTLink server → client → scene.
#include <gtest/gtest.h>

#include <algorithm>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>
#include <set>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>
#include <vtkCallbackCommand.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include "rpIgtlClient.h"
#include "rpIgtlServer.h"
#include "rpTrackingTestHelpers.h"
#include "rpNdiTracker.h"
#include "rpNdiRom.h"
#include "rpPolarisSimulator.h"
#include "rpPlusSequenceFile.h"
#include "rpTrackingCommands.h"
#include "rpTrackingRecording.h"
#include "vtkRPScene.h"
#include "vtkRPTrackedToolNode.h"
#include "vtkRPTrackingLogic.h"

using namespace rp;
using test::FreePort;
using test::TestMatrix;
using test::WaitFor;

namespace {
vtkRPTrackedToolNode* ToolNode(vtkRPScene* scene, const char* name) {
  return vtkRPTrackedToolNode::SafeDownCast(scene->GetFirstNodeByName(name));
}
std::string OutputDir() {
  std::filesystem::create_directories(ROBOPLAN_TEST_OUTPUT_DIR);
  return ROBOPLAN_TEST_OUTPUT_DIR;
}
ToolDefinition Tool(const std::string& name) {
  return ReadToolDefinition(std::string(ROBOPLAN_RESOURCES_DIR) + "/Tools/" + name + ".json");
}
}  // namespace

TEST(TrackingLogic, BatchUpdateStaleDroppedAndReference) {
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPTrackingLogic> logic;
  logic->SetScene(scene);
  logic->SetStaleTimeout(0.5);
  logic->SetReferenceNodeName("ReferenceToTracker");
  ToolPoseTable table;
  const int stylus = table.FindOrAdd("StylusToTracker");
  const int reference = table.FindOrAdd("ReferenceToTracker");
  logic->AddPoseTable(&table);

  int batches = 0;
  vtkNew<vtkCallbackCommand> counter;
  counter->SetClientData(&batches);
  counter->SetCallback([](vtkObject*, unsigned long, void* data, void*) { ++*static_cast<int*>(data); });
  scene->AddObserver(vtkRPScene::EndBatchProcessEvent, counter);

  const double t0 = 1000.0;
  ToolPose p;
  p.State = ToolState::OK;
  p.Translation[0] = 10;
  p.ReceiveTime = t0;
  for (int i = 0; i < 5; ++i) {  // five poses before the main thread looks: four dropped
    p.Translation[1] = i;
    table.Publish(stylus, p);
  }
  ToolPose r;
  r.State = ToolState::OK;
  r.Translation[0] = 4;
  r.ReceiveTime = t0;
  table.Publish(reference, r);
  EXPECT_EQ(logic->UpdateNodes(t0 + 0.01), 3);  // Stylus, Reference, StylusToReference
  EXPECT_EQ(batches, 1);
  vtkRPTrackedToolNode* node = ToolNode(scene, "StylusToTracker");
  ASSERT_NE(node, nullptr);
  EXPECT_EQ(node->GetStatus(), vtkRPTrackedToolNode::StatusOK);
  EXPECT_DOUBLE_EQ(node->GetMatrixTransformToParent()->GetElement(1, 3), 4.0);  // the newest
  vtkRPTrackedToolNode* relative = ToolNode(scene, "StylusToReference");
  ASSERT_NE(relative, nullptr);
  EXPECT_DOUBLE_EQ(relative->GetMatrixTransformToParent()->GetElement(0, 3), 6.0);
  const auto stats = logic->GetToolStatistics();
  ASSERT_EQ(stats.size(), 2u);
  EXPECT_EQ(stats[0].Frames.Ok, 5u);
  EXPECT_EQ(stats[0].Dropped, 4u);

  // Nothing new: nodes untouched until the stale timeout, then marked stale once.
  const auto mtime = node->GetMTime();
  EXPECT_EQ(logic->UpdateNodes(t0 + 0.2), 0);
  EXPECT_EQ(node->GetMTime(), mtime);
  logic->UpdateNodes(t0 + 0.6);
  EXPECT_EQ(node->GetStatus(), vtkRPTrackedToolNode::StatusStale);
  EXPECT_EQ(relative->GetStatus(), vtkRPTrackedToolNode::StatusStale);

  // Missing keeps the last matrix but says so.
  p.State = ToolState::Missing;
  p.ReceiveTime = t0 + 0.7;
  table.Publish(stylus, p);
  logic->UpdateNodes(t0 + 0.7);
  EXPECT_EQ(node->GetStatus(), vtkRPTrackedToolNode::StatusMissing);
  EXPECT_DOUBLE_EQ(node->GetMatrixTransformToParent()->GetElement(1, 3), 4.0);

  // Deleting a node that receives data: no crash, re-created on the next pose.
  scene->RemoveNode(node);
  EXPECT_EQ(ToolNode(scene, "StylusToTracker"), nullptr);
  p.State = ToolState::OK;
  p.ReceiveTime = t0 + 0.8;
  table.Publish(stylus, p);
  logic->UpdateNodes(t0 + 0.8);
  ASSERT_NE(ToolNode(scene, "StylusToTracker"), nullptr);
  EXPECT_EQ(ToolNode(scene, "StylusToTracker")->GetStatus(), vtkRPTrackedToolNode::StatusOK);
  logic->SetAutoCreateNodes(false);
  scene->RemoveNode(ToolNode(scene, "StylusToTracker"));
  table.Publish(stylus, p);
  logic->UpdateNodes(t0 + 0.9);
  EXPECT_EQ(ToolNode(scene, "StylusToTracker"), nullptr);
}

// A writer thread publishing at 2 kHz while the main thread updates and deletes nodes (TSan).
TEST(TrackingLogic, ConcurrentPublishingAndNodeDeletion) {
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPTrackingLogic> logic;
  logic->SetScene(scene);
  ToolPoseTable table;
  std::atomic<bool> stop{false};
  std::thread writer([&] {
    const int a = table.FindOrAdd("AToTracker"), b = table.FindOrAdd("BToTracker");
    ToolPose p;
    p.State = ToolState::OK;
    for (int i = 0; !stop; ++i) {
      p.Translation[0] = i;
      p.ReceiveTime = SteadySeconds();
      table.Publish(i % 2 ? a : b, p);
      if (i == 500) table.FindOrAdd("CToTracker");  // a tool appearing while the reader runs
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
  });
  logic->AddPoseTable(&table);
  for (int k = 0; k < 100; ++k) {
    logic->UpdateNodes(SteadySeconds());
    if (k % 10 == 5)
      if (auto* n = ToolNode(scene, "AToTracker")) scene->RemoveNode(n);
    std::this_thread::sleep_for(std::chrono::milliseconds(3));
  }
  stop = true;
  writer.join();
  logic->UpdateNodes(SteadySeconds());
  ASSERT_NE(ToolNode(scene, "BToTracker"), nullptr);
  uint64_t received = 0;
  for (const auto& s : logic->GetToolStatistics()) received += s.Frames.WithPose();
  EXPECT_GT(received, 200u);
}

TEST(TrackingLogic, SimulatorThroughSerialAndOpenIGTLinkIntoTheScene) {
  PolarisSimulator::Options so;
  so.LinkPath = OutputDir() + "/chain";
  PolarisSimulator sim(so);
  const ToolDefinition stylus = Tool("Stylus"), reference = Tool("Reference");
  sim.AddTool(stylus);
  sim.AddTool(reference);
  std::string error;
  ASSERT_TRUE(sim.Start(error)) << error;
  NdiTracker::Options o;
  o.Port = sim.PortPath();
  o.Tools = {{"Stylus", stylus.Rom}, {"Reference", reference.Rom}};
  o.CommandTimeoutMs = 1000;
  NdiTracker tracker(o);
  tracker.Start();
  IgtlServer::Options serverOptions;
  serverOptions.Port = 0;
  IgtlServer server(tracker.Poses(), serverOptions);
  ASSERT_TRUE(server.Start(error)) << error;
  IgtlClient::Options co;
  co.Port = server.Port();
  IgtlClient client(co);
  client.Start();

  vtkNew<vtkRPScene> serialScene, igtlScene;
  vtkNew<vtkRPTrackingLogic> serialLogic, igtlLogic;
  serialLogic->SetScene(serialScene);
  serialLogic->AddPoseTable(&tracker.Poses());
  igtlLogic->SetScene(igtlScene);
  igtlLogic->AddPoseTable(&client.Poses());
  ASSERT_TRUE(WaitFor([&] {
    serialLogic->UpdateNodes(SteadySeconds());
    igtlLogic->UpdateNodes(SteadySeconds());
    auto* a = ToolNode(igtlScene, "ReferenceToTracker");
    return a && a->GetStatus() == vtkRPTrackedToolNode::StatusOK;
  }, 5)) << tracker.LastError() << " / " << client.LastError();
  // The static reference: same matrix in both scenes (float transport).
  auto* viaSerial = ToolNode(serialScene, "ReferenceToTracker");
  auto* viaIgtl = ToolNode(igtlScene, "ReferenceToTracker");
  ASSERT_NE(viaSerial, nullptr);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      EXPECT_NEAR(viaSerial->GetMatrixTransformToParent()->GetElement(r, c),
                  viaIgtl->GetMatrixTransformToParent()->GetElement(r, c), c == 3 ? 1e-3 : 1e-6);
  // Occlusion: Missing on the serial side; PLUS-style v1 server goes silent → stale over IGTL.
  igtlLogic->SetStaleTimeout(0.3);
  sim.SetOccluded("Reference", true);
  EXPECT_TRUE(WaitFor([&] {
    serialLogic->UpdateNodes(SteadySeconds());
    igtlLogic->UpdateNodes(SteadySeconds());
    return viaSerial->GetStatus() == vtkRPTrackedToolNode::StatusMissing &&
           viaIgtl->GetStatus() == vtkRPTrackedToolNode::StatusStale;
  }, 3));
  client.Stop();
  server.Stop();
  tracker.Stop();
  sim.Stop();
}

// The logic calls behind `tool-info` and `polaris-sim`: a tool's .json and its NDI .rom read to
// the same markers, bad files named; a simulated Polaris started by the logic is tracked by the
// logic's own serial source (one path from the command line and from a panel).
TEST(TrackingLogic, ToolFilesAndASimulatedPolarisThroughTheLogic) {
  const std::string tools = std::string(ROBOPLAN_RESOURCES_DIR) + "/Tools/";
  rom::Definition fromJson, fromRom;
  std::vector<uint8_t> jsonRom, romBytes;
  std::string error;
  ASSERT_TRUE(vtkRPTrackingLogic::ReadToolDefinitionFile(tools + "Stylus.json", fromJson, jsonRom, error)) << error;
  ASSERT_TRUE(vtkRPTrackingLogic::ReadToolDefinitionFile(tools + "Stylus.rom", fromRom, romBytes, error)) << error;
  EXPECT_EQ(jsonRom, romBytes);  // the .rom in Resources is the one the .json makes
  ASSERT_EQ(fromJson.Markers.size(), Tool("Stylus").Markers.size());
  for (size_t m = 0; m < fromJson.Markers.size(); ++m)
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(fromJson.Markers[m][a], Tool("Stylus").Markers[m][a], 1e-4);
  const std::string garbage = OutputDir() + "/garbage.rom";
  std::ofstream(garbage) << "not a tool definition\n";
  EXPECT_FALSE(vtkRPTrackingLogic::ReadToolDefinitionFile(garbage, fromRom, romBytes, error));
  EXPECT_NE(error.find("garbage.rom"), std::string::npos) << error;
  EXPECT_FALSE(vtkRPTrackingLogic::ReadToolDefinitionFile(OutputDir() + "/missing.json", fromRom, romBytes, error));
  EXPECT_NE(error.find("missing.json"), std::string::npos) << error;

  PolarisSimulator::Options so;
  so.LinkPath = OutputDir() + "/logic-sim";
  const std::unique_ptr<PolarisSimulator> sim =
      vtkRPTrackingLogic::StartSimulatedPolaris(so, {Tool("Reference")}, {-1}, error);
  ASSERT_NE(sim, nullptr) << error;
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPTrackingLogic> logic;
  logic->SetScene(scene);
  PoseSourceConfig config;
  config.Kind = "serial";
  config.Address = sim->PortPath();
  config.ToolFiles = {tools + "Reference.json"};
  ASSERT_GE(logic->Connect(config, error), 0) << error;
  EXPECT_TRUE(WaitFor([&] {
    logic->UpdateNodes(SteadySeconds());
    auto* node = ToolNode(scene, "ReferenceToTracker");
    return node && node->GetStatus() == vtkRPTrackedToolNode::StatusOK;
  }, 5));
}

namespace {
// track --record on the simulator, then pivot and --replay read the file (format by extension).
void TrackRecordPivotAndReplay(const std::string& file) {
  const std::string link = OutputDir() + "/cli-" + file;
  std::atomic<bool> stop{false};
  std::ostringstream simOut, simErr;
  std::thread simThread([&] {
    RunPolarisSimCommand({"--port-link", link, "--noise", "0.05", "--noise-deg", "0"}, simOut, simErr, &stop);
  });
  ASSERT_TRUE(WaitFor([&] { return std::filesystem::exists(link + ".break"); }, 3));
  const std::string resources = std::string(ROBOPLAN_RESOURCES_DIR) + "/Tools/";
  const std::string recording = OutputDir() + "/" + file;
  std::ostringstream out, err;
  const int code = RunTrackCommand({"--serial", link, "--rom", resources + "Stylus.json", "--rom", resources + "Reference.json",
                                    "--seconds", "2", "--record", recording, "--json"},
                                   nullptr, out, err);
  ASSERT_EQ(code, 0) << err.str();
  EXPECT_NE(out.str().find("\"StylusToTracker\""), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("\"status\": \"OK\""), std::string::npos);
  std::ostringstream pout, perr;
  ASSERT_EQ(RunPivotCommand({recording, "--json"}, pout, perr), 0) << perr.str() << pout.str();
  // Tip offset from 2 s of 60 Hz BX poses with 0.05 mm noise: within 0.5 mm of the definition.
  const ToolDefinition stylus = Tool("Stylus");
  std::istringstream text(pout.str());
  const std::string json = pout.str();
  const size_t at = json.find("\"tipOffsetMm\"");
  ASSERT_NE(at, std::string::npos);
  std::string numbers = json.substr(json.find('[', at) + 1, json.find(']', at) - json.find('[', at) - 1);
  for (char& c : numbers)
    if (c == ',') c = ' ';
  std::istringstream values(numbers);
  for (int k = 0; k < 3; ++k) {
    double v;
    values >> v;
    EXPECT_NEAR(v, stylus.TipOffset[static_cast<size_t>(k)], 0.5) << k;
  }
  // The recording replays as a tracker (4x speed: the 2 s session in 0.5 s) and the command ends
  // with it, well before --seconds (a time limit, not a wait: a loaded machine plays late).
  std::ostringstream rout, rerr;
  const double replayStart = SteadySeconds();
  ASSERT_EQ(RunTrackCommand({"--replay", recording, "--speed", "4", "--seconds", "20", "--json"}, nullptr, rout, rerr), 0)
      << rerr.str();
  EXPECT_LT(SteadySeconds() - replayStart, 15.0);
  EXPECT_NE(rout.str().find("\"finished\": true"), std::string::npos) << rout.str();
  EXPECT_NE(rout.str().find("\"StylusToTracker\""), std::string::npos);
  stop = true;
  simThread.join();
}
}  // namespace

TEST(TrackingLogic, TrackAndPivotCommandsOnTheSimulator) {
  TrackRecordPivotAndReplay("session.rec");
  // Bad arguments.
  std::ostringstream bout, berr;
  EXPECT_EQ(RunTrackCommand({"--seconds", "1"}, nullptr, bout, berr), 2);
  EXPECT_NE(berr.str().find("exactly one of --serial"), std::string::npos);
  EXPECT_EQ(RunTrackCommand({"--igtl", "localhost"}, nullptr, bout, berr), 2);
}

TEST(TrackingLogic, TrackRecordsPlusSequencesThatPivotAndReplayRead) {
  for (const std::string file : {"session.igs.mha", "session.igs.nrrd"}) {
    SCOPED_TRACE(file);
    TrackRecordPivotAndReplay(file);
    // A PLUS tracked-frame sequence: PLUS's transform names, a frame per camera frame, statuses.
    const PlusSequence sequence = ReadPlusSequence(OutputDir() + "/" + file);
    EXPECT_NE(std::find(sequence.TransformNames.begin(), sequence.TransformNames.end(), "StylusToTracker"),
              sequence.TransformNames.end());
    EXPECT_NE(std::find(sequence.TransformNames.begin(), sequence.TransformNames.end(), "ReferenceToTracker"),
              sequence.TransformNames.end());
    EXPECT_GT(sequence.Frames.size(), 60u);  // 2 s at 60 Hz, whatever a loaded machine drops
  }
  std::ostringstream out, err;  // an unwritable PLUS file is named before tracking starts
  EXPECT_EQ(RunTrackCommand({"--simulate", "--seconds", "0.2", "--record", "/nonexistent/x.igs.mha"}, nullptr, out, err), 1);
  EXPECT_NE(err.str().find("/nonexistent/x.igs.mha"), std::string::npos) << err.str();
}

TEST(TrackingLogic, TrackCommandAt20HzServingOpenIGTLink) {
  const std::string link = OutputDir() + "/cli20";
  std::atomic<bool> stop{false};
  std::ostringstream simOut, simErr;
  std::thread simThread([&] { RunPolarisSimCommand({"--port-link", link, "--rate", "60"}, simOut, simErr, &stop); });
  ASSERT_TRUE(WaitFor([&] { return std::filesystem::exists(link + ".break"); }, 3));
  const int port = FreePort();  // for --serve
  IgtlClient::Options co;
  co.Port = port;
  co.ReconnectInitialSeconds = 0.05;
  co.ReconnectMaxSeconds = 0.1;
  IgtlClient client(co);
  client.Start();
  const std::string rom = std::string(ROBOPLAN_RESOURCES_DIR) + "/Tools/Stylus.rom";  // a plain .rom file
  std::ostringstream out, err;
  ASSERT_EQ(RunTrackCommand({"--serial", link, "--rom", rom, "--rate", "20", "--seconds", "1.5", "--serve",
                             std::to_string(port), "--json"},
                            nullptr, out, err),
            0)
      << err.str();
  // IRATE 2 -> 0: the simulated camera now runs at 20 Hz (not its 60 Hz) and the driver polls at
  // 20 Hz. The rate is poses over wall-clock seconds, set-up included: a loaded machine schedules
  // the poll and the camera late and loses frames (16 Hz with both cores busy), never adds any.
  const std::string json = out.str();
  const size_t at = json.find("\"rateHz\"");
  ASSERT_NE(at, std::string::npos) << json;
  const double rate = std::stod(json.substr(json.find(':', at) + 1));
  EXPECT_LE(rate, 23.0) << json;
  EXPECT_GE(rate, 10.0) << json;
  EXPECT_NE(json.find("\"name\": \"StylusToTracker\""), std::string::npos);  // named after Stylus.rom
  EXPECT_GT(client.GetStatistics().Poses, 10u) << client.LastError();
  EXPECT_GE(client.Poses().Find("StylusToTracker", 15), 0);
  client.Stop();
  stop = true;
  simThread.join();
}

// Wired tools without a PLUS configuration: `polaris-sim --wired PORT=FILE` plugs a tool into a
// wired port, `track --serial ... --wired NAME=PORT` finds it there (PLUS's PortName numbering)
// beside a passive tool; a malformed --wired is named.
TEST(TrackingLogic, TrackFindsAWiredToolThePolarisSimulatorHasInAPort) {
  const std::string link = OutputDir() + "/cli-wired";
  const std::string tools = std::string(ROBOPLAN_RESOURCES_DIR) + "/Tools/";
  std::atomic<bool> stop{false};
  std::ostringstream simOut, simErr;
  std::thread simThread([&] {
    RunPolarisSimCommand({"--port-link", link, "--tool", tools + "Reference.json", "--wired", "1=" + tools + "Stylus.json"},
                         simOut, simErr, &stop);
  });
  ASSERT_TRUE(WaitFor([&] { return std::filesystem::exists(link + ".break"); }, 3));
  std::ostringstream out, err;
  ASSERT_EQ(RunTrackCommand({"--serial", link, "--rom", tools + "Reference.json", "--wired", "Pointer=1", "--seconds", "1",
                             "--json"},
                            nullptr, out, err),
            0)
      << err.str();
  const auto doc = nlohmann::json::parse(out.str());
  std::set<std::string> ok;
  for (const auto& t : doc["tools"])
    if (t["status"] == "OK") ok.insert(t["name"].get<std::string>());
  EXPECT_EQ(ok, (std::set<std::string>{"PointerToTracker", "ReferenceToTracker"})) << out.str();
  std::ostringstream badOut, badErr;
  EXPECT_EQ(RunTrackCommand({"--serial", link, "--wired", "Pointer", "--seconds", "1"}, nullptr, badOut, badErr), 2);
  EXPECT_NE(badErr.str().find("wired tool 'Pointer': give NAME=PORT"), std::string::npos) << badErr.str();
  stop = true;
  simThread.join();
  std::ostringstream simBadOut, simBadErr;
  EXPECT_NE(RunPolarisSimCommand({"--wired", "port1=" + tools + "Stylus.json"}, simBadOut, simBadErr), 0);
  EXPECT_NE(simBadErr.str().find("give PORT=FILE"), std::string::npos) << simBadErr.str();
}

TEST(TrackingLogic, CommandsPrintTheirOwnUsage) {
  // The host prefixes "roboplan": each command names itself once ("usage: roboplan track").
  const std::vector<std::pair<std::string, std::function<int(std::ostream&, std::ostream&)>>> commands = {
      {"track", [](std::ostream& o, std::ostream& e) { return RunTrackCommand({"--help"}, nullptr, o, e); }},
      {"pivot", [](std::ostream& o, std::ostream& e) { return RunPivotCommand({"--help"}, o, e); }},
      {"polaris-sim", [](std::ostream& o, std::ostream& e) { return RunPolarisSimCommand({"--help"}, o, e); }}};
  for (const auto& [name, run] : commands) {
    std::ostringstream out, err;
    EXPECT_EQ(run(out, err), 0) << name;
    const std::string usage = out.str() + err.str();
    EXPECT_EQ(usage.rfind("usage: roboplan " + name, 0), 0u) << usage;
    EXPECT_EQ(usage.find("roboplan roboplan"), std::string::npos) << usage;
  }
}
