// PLUS device-set configurations: the ten real files of PlusLibData read as PLUS reads them
// (tools, ROM paths, fixed transforms, the server section, what is refused), malformed and
// damaged files, PLUS's transform repository on analytic chains, `roboplan track --plus-config
// --check` on every real file, and a configuration run end to end on the simulator with the
// served StylusTipToReference checked against the simulator's true poses.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <sstream>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "rpPlusConfiguration.h"
#include "rpPolarisSimulator.h"
#include "rpPlusTracking.h"
#include "rpSharedData.h"
#include "rpTrackingCommands.h"
#include "rpTransformRepository.h"

using namespace rp;

namespace {
const std::string kConfigs = std::string(ROBOPLAN_SHARED_DATA_DIR) + "/../oracles/plus-data/ConfigFiles/";

plus::Configuration Read(const std::string& relative, const plus::ResolveOptions& options = {}) {
  plus::Configuration c;
  std::string error;
  EXPECT_TRUE(plus::ReadConfiguration(kConfigs + relative, options, c, error)) << error;
  return c;
}

bool RefusedMentions(const plus::Configuration& c, const std::string& what, const std::string& why) {
  for (const auto& r : c.Refused)
    if (r.What.find(what) != std::string::npos && r.Why.find(why) != std::string::npos) return true;
  return false;
}

Eigen::Matrix4d RandomRigid(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Quaterniond q(u(rng), u(rng), u(rng), u(rng));
  q.normalize();
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = q.toRotationMatrix();
  m.topRightCorner<3, 1>() = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 500;
  return m;
}
}  // namespace

TEST(PlusConfiguration, PolarisServerConfigurationGivesToolsRomsTransformsAndServer) {
  RP_REQUIRE_SHARED_DATA(kConfigs);
  const plus::Configuration c = Read("PlusDeviceSet_Server_NDIPolaris.xml");
  ASSERT_EQ(c.Trackers.size(), 1u);
  const plus::NdiTracker& t = c.Trackers[0];
  EXPECT_EQ(t.Id, "TrackerDevice");
  EXPECT_EQ(t.Type, "PolarisTracker");
  EXPECT_EQ(t.ToolReferenceFrame, "Tracker");
  EXPECT_FALSE(t.Tcp());
  ASSERT_EQ(t.Tools.size(), 3u);
  EXPECT_EQ(t.Tools[1].Id, "Stylus");
  EXPECT_EQ(std::filesystem::path(t.Tools[1].RomPath), std::filesystem::path(kConfigs + "NdiToolDefinitions/8700340.rom").lexically_normal());
  ASSERT_EQ(c.Transforms.size(), 1u);
  EXPECT_EQ(c.Transforms[0].From, "StylusTip");
  EXPECT_EQ(c.Transforms[0].To, "Stylus");
  EXPECT_DOUBLE_EQ(c.Transforms[0].Matrix[11], -88.5321);
  EXPECT_DOUBLE_EQ(c.Transforms[0].Matrix[5], -1);
  EXPECT_DOUBLE_EQ(c.Transforms[0].Error, 0.554951);
  const plus::Server& s = c.OpenIGTLinkServer;
  ASSERT_TRUE(s.Present);
  EXPECT_EQ(s.ListeningPort, 18944);
  EXPECT_EQ(s.OutputChannelId, "TrackerStream");
  EXPECT_TRUE(s.SendValidTransformsOnly);
  EXPECT_EQ(s.MessageTypes, std::vector<std::string>{"TRANSFORM"});
  ASSERT_EQ(s.TransformNames.size(), 5u);
  EXPECT_EQ(s.TransformNames[0].Name, "StylusTipToReference");
  // The recording device is the only thing refused, in one message that names it.
  ASSERT_EQ(c.Refused.size(), 1u);
  EXPECT_NE(c.RefusedMessage().find("CaptureDevice (VirtualCapture)"), std::string::npos) << c.RefusedMessage();
}

TEST(PlusConfiguration, VegaOverTcpAndSerialPortNumbersAsPlusMapsThem) {
  RP_REQUIRE_SHARED_DATA(kConfigs);
  const plus::Configuration vega = Read("PlusDeviceSet_Server_NDIVega.xml");
  ASSERT_EQ(vega.Trackers.size(), 1u);
  EXPECT_TRUE(vega.Trackers[0].Tcp());
  EXPECT_EQ(vega.Trackers[0].NetworkHostname, "192.168.0.30");
  EXPECT_EQ(vega.Trackers[0].NetworkPort, 8765);
  EXPECT_EQ(vega.Trackers[0].ToolReferenceFrame, "Reference");
  EXPECT_TRUE(RefusedMentions(vega, "VideoDevice (OpenCVVideo)", "video"));
  EXPECT_TRUE(RefusedMentions(vega, "message type IMAGE", "tool poses only"));
  // Aurora + Polaris: SerialPort 6 is ndicapi's /dev/ttyUSB3 on Linux; the EM pointer is a wired
  // tool in port 1 (PortName 0), defined by the SROM in the tool.
  const plus::Configuration both = Read("PlusDeviceSet_Server_NDIAurora_NDIPolaris.xml");
  ASSERT_EQ(both.Trackers.size(), 2u);
  EXPECT_EQ(both.Trackers[1].SerialDevice, "/dev/ttyUSB3");
  EXPECT_EQ(both.Trackers[1].BaudRate, 115200);
  EXPECT_DOUBLE_EQ(both.Trackers[1].AcquisitionRate, 20);
  ASSERT_EQ(both.Trackers[0].Tools.size(), 1u);
  EXPECT_EQ(both.Trackers[0].Tools[0].Id, "Pointer");
  EXPECT_EQ(both.Trackers[0].Tools[0].WiredPort, 0);
  EXPECT_TRUE(both.Trackers[0].Tools[0].RomPath.empty());
  EXPECT_FALSE(RefusedMentions(both, "tool Pointer", ""));
  EXPECT_TRUE(RefusedMentions(both, "CombinedTracker (VirtualMixer)", "mixer"));
  EXPECT_EQ(plus::SerialDeviceForPort(1), "/dev/ttyS0");
  EXPECT_EQ(plus::SerialDeviceForPort(3), "/dev/ttyUSB0");
  EXPECT_EQ(plus::SerialDeviceForPort(9), "");
}

TEST(PlusConfiguration, RomFilesResolveFromTheConfigurationFolderUpAndFromTheGivenDirectoryFirst) {
  RP_REQUIRE_SHARED_DATA(kConfigs);
  // Robarts/: "../NdiToolDefinitions/8700248.rom" from its own folder; MagStylus.rom exists
  // nowhere and is refused with the paths tried.
  const plus::Configuration robarts = Read("Robarts/PlusDeviceSet_Server_NDIPolaris_2Stylus.xml");
  ASSERT_EQ(robarts.Trackers[0].Tools.size(), 1u);
  EXPECT_EQ(robarts.Trackers[0].Tools[0].Id, "Stylus");
  EXPECT_TRUE(RefusedMentions(robarts, "tool MagStylus", "not found (tried"));
  // StableTest/: "NdiToolDefinitions/8700339.rom" is found in the parent (PLUS run from ConfigFiles).
  EXPECT_EQ(Read("StableTest/PlusDeviceSet_StableTest_NDIPolaris.xml").Trackers[0].Tools.size(), 3u);
  // A DeviceSetConfigurationDirectory given is tried first: a copy of the stylus ROM there wins.
  const std::string dir = std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/plusdir";
  std::filesystem::create_directories(dir + "/NdiToolDefinitions");
  std::filesystem::copy_file(kConfigs + "NdiToolDefinitions/8700340.rom", dir + "/NdiToolDefinitions/8700340.rom",
                             std::filesystem::copy_options::overwrite_existing);
  plus::ResolveOptions options;
  options.DeviceSetConfigurationDirectory = dir;
  const plus::Configuration c = Read("PlusDeviceSet_Server_NDIPolaris.xml", options);
  EXPECT_EQ(c.Trackers[0].Tools[1].RomPath, dir + "/NdiToolDefinitions/8700340.rom");
  EXPECT_EQ(c.Trackers[0].Tools[0].RomPath.find(dir), std::string::npos);  // 8700339 is not there: the usual place
}

TEST(PlusConfiguration, MalformedAndOddFilesGiveClearErrorsAndNeverCrash) {
  plus::Configuration c;
  std::string error;
  EXPECT_FALSE(plus::ParseConfiguration("<PlusConfiguration>\n<DataCollection>\n</PlusConfiguration>", "bad.xml", {}, c, error));
  EXPECT_NE(error.find("line 3"), std::string::npos) << error;
  EXPECT_FALSE(plus::ParseConfiguration("<Scene/>", "scene.xml", {}, c, error));
  EXPECT_NE(error.find("not a PLUS configuration"), std::string::npos) << error;
  EXPECT_FALSE(plus::ReadConfiguration(std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/absent.xml", {}, c, error));
  // Odd but well-formed: every problem becomes a refusal, nothing else.
  ASSERT_TRUE(plus::ParseConfiguration(R"(<PlusConfiguration><DataCollection>
      <Device Type="PolarisTracker" SerialPort="x" BaudRate="7" NetworkPort="99999"><DataSources>
        <DataSource Type="Tool"/><DataSource Type="Tool" Id="A" RomFile="/no/such.rom"/><DataSource Type="Video" Id="V"/>
      </DataSources></Device></DataCollection>
      <CoordinateDefinitions><Transform From="A" To="B" Matrix="1 0 0"/><Transform From="C" To="D" Matrix="1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 2"/>
      </CoordinateDefinitions>
      <PlusOpenIGTLinkServer ListeningPort="port"><DefaultClientInfo><TransformNames><Transform/></TransformNames>
      </DefaultClientInfo></PlusOpenIGTLinkServer></PlusConfiguration>)",
                                       "odd.xml", {}, c, error))
      << error;
  EXPECT_EQ(c.Trackers.size(), 1u);
  EXPECT_TRUE(c.Trackers[0].Tools.empty());
  EXPECT_TRUE(c.Transforms.empty());
  for (const char* what : {"SerialPort", "BaudRate", "NetworkPort", "has no Id", "tool A", "DataSource V", "Transform AToB",
                           "Transform CToD", "ListeningPort", "PlusOpenIGTLinkServer transform"})
    EXPECT_TRUE(RefusedMentions(c, what, "") || c.RefusedMessage().find(what) != std::string::npos) << what << "\n" << c.RefusedMessage();
}

TEST(PlusConfiguration, RandomDamageToRealConfigurationsNeverCrashes) {
  RP_REQUIRE_SHARED_DATA(kConfigs);
  std::mt19937 rng(27);
  int parsed = 0, refused = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(kConfigs)) {
    if (entry.path().extension() != ".xml") continue;
    std::ifstream in(entry.path());
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (int i = 0; i < 60; ++i) {
      std::string damaged = text;
      const int edits = std::uniform_int_distribution<int>(1, 8)(rng);
      for (int k = 0; k < edits && !damaged.empty(); ++k) {
        const size_t at = std::uniform_int_distribution<size_t>(0, damaged.size() - 1)(rng);
        switch (rng() % 3) {
          case 0: damaged[at] = "<>\"= /A0\n"[rng() % 9]; break;
          case 1: damaged.erase(at, rng() % 40); break;
          default: damaged.insert(at, damaged.substr(rng() % damaged.size(), rng() % 80)); break;
        }
      }
      plus::Configuration c;
      std::string error;
      (plus::ParseConfiguration(damaged, entry.path().string(), {}, c, error) ? parsed : refused)++;
      nlohmann::json doc = plus::ToJson(c);  // and the report of whatever was read
      EXPECT_TRUE(doc.is_object());
    }
  }
  EXPECT_GT(parsed, 0);
  EXPECT_GT(refused, 0);
}

TEST(TransformRepository, ChainsComposeWithInversesAsTheDirectProduct) {
  std::mt19937 rng(1);
  const Eigen::Matrix4d tipToStylus = RandomRigid(rng), stylusToTracker = RandomRigid(rng),
                        referenceToTracker = RandomRigid(rng), toolToTracker = RandomRigid(rng);
  TransformRepository repo;
  std::string error;
  ASSERT_TRUE(repo.SetFixed("StylusTip", "Stylus", tipToStylus, error)) << error;
  const int stylus = repo.DeclareLive("Stylus", "Tracker", error);
  const int reference = repo.DeclareLive("Reference", "Tracker", error);
  const int tool = repo.DeclareLive("Tool", "Tracker", error);
  ASSERT_GE(stylus, 0);
  Eigen::Matrix4d m;
  TransformStatus status;
  EXPECT_FALSE(repo.Get("StylusTipToReference", m, status));
  EXPECT_EQ(status, TransformStatus::Missing);  // connected, no pose yet
  repo.SetLive(stylus, stylusToTracker, TransformStatus::OK);
  repo.SetLive(reference, referenceToTracker, TransformStatus::OK);
  repo.SetLive(tool, toolToTracker, TransformStatus::OK);
  ASSERT_TRUE(repo.Get("StylusTipToReference", m, status));
  EXPECT_TRUE(m.isApprox(referenceToTracker.inverse() * stylusToTracker * tipToStylus, 1e-12));
  ASSERT_TRUE(repo.Get("Reference", "StylusTip", m, status));
  EXPECT_TRUE(m.isApprox((referenceToTracker.inverse() * stylusToTracker * tipToStylus).inverse(), 1e-12));
  ASSERT_TRUE(repo.Get("ToolToStylusTip", m, status));
  EXPECT_TRUE(m.isApprox(tipToStylus.inverse() * stylusToTracker.inverse() * toolToTracker, 1e-12));
  EXPECT_EQ(repo.Describe(repo.Prepare("StylusTip", "Reference")), "ReferenceToTracker^-1 * StylusToTracker * StylusTipToStylus");
  // A tool out of view: the chains through it are MISSING, the others stay OK.
  repo.SetLive(reference, Eigen::Matrix4d::Identity(), TransformStatus::Missing);
  EXPECT_FALSE(repo.Get("StylusTipToReference", m, status));
  EXPECT_EQ(status, TransformStatus::Missing);
  EXPECT_TRUE(m.isApprox(referenceToTracker.inverse() * stylusToTracker * tipToStylus, 1e-12));  // the last matrix kept
  EXPECT_TRUE(repo.Get("ToolToTracker", m, status));
  // Not connected, unknown, malformed: INVALID.
  ASSERT_TRUE(repo.SetFixed("Image", "Probe", RandomRigid(rng), error));
  EXPECT_FALSE(repo.Get("ImageToTracker", m, status));
  EXPECT_EQ(status, TransformStatus::Invalid);
  EXPECT_FALSE(repo.Get("NobodyToTracker", m, status));
  EXPECT_EQ(status, TransformStatus::Invalid);
  EXPECT_FALSE(repo.Get("Stylustracker", m, status));
  EXPECT_EQ(status, TransformStatus::Invalid);
  // A second path between connected frames is refused, as PLUS refuses it.
  EXPECT_FALSE(repo.SetFixed("StylusTip", "Reference", RandomRigid(rng), error));
  EXPECT_NE(error.find("already defined or computable"), std::string::npos) << error;
  EXPECT_FALSE(repo.SetFixed("Stylus", "StylusTip", RandomRigid(rng), error));  // its own inverse
}

TEST(TransformRepository, NamesSplitAtTheOneToBeforeACapital) {
  std::string from, to, error;
  ASSERT_TRUE(SplitTransformName("ToolToReference", from, to, error));
  EXPECT_EQ(from, "Tool");
  EXPECT_EQ(to, "Reference");
  ASSERT_TRUE(SplitTransformName("MagStylusTipToReference", from, to, error));
  EXPECT_EQ(from, "MagStylusTip");
  EXPECT_FALSE(SplitTransformName("StylusTipToTopToReference", from, to, error));
  EXPECT_NE(error.find("ambiguous"), std::string::npos);
  EXPECT_FALSE(SplitTransformName("Stylus", from, to, error));
}

TEST(PlusConfiguration, CheckPrintsEveryRealConfigurationWithoutOpeningADevice) {
  RP_REQUIRE_SHARED_DATA(kConfigs);
  int files = 0, runnable = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(kConfigs)) {
    if (entry.path().extension() != ".xml") continue;
    ++files;
    std::ostringstream out, err;
    const int code = RunTrackCommand({"--plus-config", entry.path().string(), "--check", "--json"}, nullptr, out, err);
    const auto doc = nlohmann::json::parse(out.str());
    EXPECT_TRUE(doc.contains("trackers") && doc.contains("refused") && doc.contains("served")) << entry.path();
    // Scripts rely on the exit code: 0 when a tracker of the file runs, 1 when none can.
    EXPECT_EQ(code, doc["runs"].is_null() ? 1 : 0) << entry.path() << "\n" << err.str();
    runnable += doc["runs"].is_null() ? 0 : 1;
  }
  EXPECT_EQ(files, 10);
  EXPECT_EQ(runnable, 8);  // all but fCal's two simulated ones (no NDI tracker in them)
  std::ostringstream none, noneErr;
  EXPECT_EQ(RunTrackCommand({"--plus-config", kConfigs + "PlusDeviceSet_fCal_Sim_RecordPhantomLandmarks.xml", "--check"},
                            nullptr, none, noneErr),
            1);
  EXPECT_NE(none.str().find("no NDI tracker RoboPlan can run"), std::string::npos) << none.str();
  EXPECT_NE(noneErr.str().find("no NDI tracker RoboPlan can run"), std::string::npos) << noneErr.str();
  std::ostringstream out, err;
  ASSERT_EQ(RunTrackCommand({"--plus-config", kConfigs + "PlusDeviceSet_Server_NDIPolaris.xml", "--check"}, nullptr, out, err), 0);
  EXPECT_NE(out.str().find("StylusTipToReference = ReferenceToTracker^-1 * StylusToTracker * StylusTipToStylus"), std::string::npos)
      << out.str();
  std::ostringstream out2, err2;
  EXPECT_EQ(RunTrackCommand({"--plus-config", kConfigs + "PlusDeviceSet_fCal_Sim_RecordPhantomLandmarks.xml"}, nullptr, out2, err2), 1);
  EXPECT_NE(err2.str().find("no NDI tracker RoboPlan can run"), std::string::npos) << err2.str();
}

TEST(PlusConfiguration, RunsOnTheSimulatorAndServesStylusTipToReference) {
  RP_REQUIRE_SHARED_DATA(kConfigs);
  // The simulator carries the configuration's own ROMs (tools standing still 150 mm apart along
  // x, no rotation): StylusTipToReference = StylusTipToStylus shifted by Stylus - Reference.
  std::ostringstream out, err;
  ASSERT_EQ(RunTrackCommand({"--plus-config", kConfigs + "PlusDeviceSet_Server_NDIPolaris.xml", "--simulate", "--seconds",
                             "1.5", "--serve", "0", "--json"},
                            nullptr, out, err),
            0)
      << err.str();
  const auto doc = nlohmann::json::parse(out.str());
  bool found = false;
  for (const auto& t : doc["plusTransforms"]) {
    if (t["name"] != "StylusTipToReference") continue;
    found = true;
    EXPECT_EQ(t["state"], "OK");
    EXPECT_GT(t["published"].get<int>(), 10);
    // Tool at x = -200, Stylus -50, Reference 100 (mm); the tip 88.53 mm along -z of the stylus.
    EXPECT_NEAR(t["position"][0].get<double>(), -150.0 + 0.018, 0.5);
    EXPECT_NEAR(t["position"][1].get<double>(), 0.0, 0.5);
    EXPECT_NEAR(t["position"][2].get<double>(), -88.5321, 0.5);
  }
  EXPECT_TRUE(found) << out.str();
  EXPECT_NE(err.str().find("CaptureDevice"), std::string::npos) << err.str();  // the refusal message
}

TEST(PlusConfiguration, VegaConfigurationRunsOverTcpAgainstTheSimulatorCarryingOnlyTheRomsItIsSent) {
  RP_REQUIRE_SHARED_DATA(kConfigs);
  // A simulated Vega on 127.0.0.1 that knows no tool: the driver uploads the file's 8700248.rom,
  // the simulator tracks it standing still at (-300, 0, -1500) mm, and StylusTipToReference is
  // served as StylusToReference * StylusTipToStylus (the Vega file's tool frame is Reference).
  PolarisSimulator::Options options;
  options.TcpPort = 0;
  PolarisSimulator vega(options);
  std::string error;
  ASSERT_TRUE(vega.Start(error)) << error;
  std::ostringstream out, err;
  ASSERT_EQ(RunTrackCommand({"--plus-config", kConfigs + "PlusDeviceSet_Server_NDIVega.xml", "--ndi-tcp", vega.PortPath(),
                             "--seconds", "1.5", "--serve", "0", "--json"},
                            nullptr, out, err),
            0)
      << err.str();
  const auto doc = nlohmann::json::parse(out.str());
  EXPECT_EQ(doc["source"], "tcp");
  EXPECT_EQ(doc["device"]["link"], "tcp");
  EXPECT_EQ(vega.ToolNames(), std::vector<std::string>{"8700248"});
  ASSERT_EQ(doc["plusTransforms"].size(), 1u);
  const auto& t = doc["plusTransforms"][0];
  EXPECT_EQ(t["name"], "StylusTipToReference");
  EXPECT_EQ(t["state"], "OK");
  EXPECT_NEAR(t["position"][0].get<double>(), -300.0 + 0.0180449, 1e-3);
  EXPECT_NEAR(t["position"][1].get<double>(), -0.00144002, 1e-3);
  EXPECT_NEAR(t["position"][2].get<double>(), -1500.0 - 88.5321, 1e-3);
  EXPECT_NE(err.str().find("VideoDevice (OpenCVVideo)"), std::string::npos) << err.str();  // refused, the rest ran
}

TEST(PlusConfiguration, PhantomRegistrationSettingsAreReadWithTheRestOfTheFile) {
  RP_REQUIRE_SHARED_DATA(kConfigs);
  // fCal's file: eight landmarks in their order, the algorithms' frames; no threshold written.
  const plus::Configuration c = Read("PlusDeviceSet_fCal_Sim_RecordPhantomLandmarks.xml");
  const plus::PhantomRegistrationSettings& p = c.PhantomRegistration;
  ASSERT_TRUE(p.HasLandmarks);
  ASSERT_EQ(p.Landmarks.size(), 8u);
  EXPECT_EQ(p.Landmarks[0].Name, "#1");
  EXPECT_DOUBLE_EQ(p.Landmarks[0].Position[0], 104.3);
  EXPECT_DOUBLE_EQ(p.Landmarks[4].Position[2], 15.0);
  EXPECT_EQ(p.PhantomFrame, "Phantom");
  EXPECT_EQ(p.StylusTipFrame, "StylusTip");
  EXPECT_EQ(p.StylusFrame, "Stylus");
  EXPECT_FALSE(p.DetectionTimeSec.has_value());
  // A landmark without a position and a threshold that is not a number are named.
  plus::Configuration bad;
  std::string error;
  ASSERT_TRUE(plus::ParseConfiguration(
      "<PlusConfiguration><PhantomDefinition><Geometry><Landmarks><Landmark Name=\"A\" Position=\"1 2\" />"
      "</Landmarks></Geometry></PhantomDefinition><vtkPlusPhantomLandmarkRegistrationAlgo DetectionTimeSec=\"soon\" />"
      "</PlusConfiguration>",
      "inline.xml", {}, bad, error))
      << error;
  EXPECT_NE(bad.PhantomRegistration.LandmarkProblem.find("landmark #1"), std::string::npos);
  EXPECT_FALSE(bad.PhantomRegistration.DetectionTimeSec.has_value());
  EXPECT_TRUE(RefusedMentions(bad, "DetectionTimeSec", "not a number"));
}

// Wired tools as PLUS configures them: PortName alone (the SROM in the tool), PortName with a
// RomFile (a virtual SROM written over it), a 5-DOF splitter's second channel (PortName 101), a
// PortName that is not a number (refused); then the file run end to end on the simulator, the
// tools found by their ports; and, of two trackers, the one --plus-device names.
TEST(PlusConfiguration, WiredToolsAreFoundByTheirPortNameAndRunOnTheSimulator) {
  RP_REQUIRE_SHARED_DATA(kConfigs);
  const std::string dir = std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/plus-wired";
  std::filesystem::create_directories(dir);
  const std::string file = dir + "/PlusDeviceSet_Server_Wired.xml";
  std::ofstream(file) << R"(<PlusConfiguration version="2.1"><DataCollection>
    <DeviceSet Name="wired tools" />
    <Device Id="TrackerDevice" Type="AuroraTracker" SerialPort="4" ToolReferenceFrame="Tracker">
      <DataSources>
        <DataSource Type="Tool" Id="Needle" PortName="0" />
        <DataSource Type="Tool" Id="Probe" PortName="101" />
        <DataSource Type="Tool" Id="Patched" PortName="2" RomFile=")" + kConfigs + R"(NdiToolDefinitions/8700449.rom" />
        <DataSource Type="Tool" Id="Odd" PortName="two" />
      </DataSources>
    </Device></DataCollection>
    <PlusOpenIGTLinkServer ListeningPort="18944"><DefaultClientInfo><MessageTypes><Message Type="TRANSFORM" /></MessageTypes>
      <TransformNames><Transform Name="NeedleToTracker" /><Transform Name="ProbeToTracker" /><Transform Name="PatchedToTracker" />
      </TransformNames></DefaultClientInfo></PlusOpenIGTLinkServer></PlusConfiguration>)";
  plus::Configuration c;
  std::string error;
  ASSERT_TRUE(plus::ReadConfiguration(file, {}, c, error)) << error;
  ASSERT_EQ(c.Trackers.size(), 1u);
  const auto& tools = c.Trackers[0].Tools;
  ASSERT_EQ(tools.size(), 3u);
  EXPECT_EQ(tools[0].WiredPort, 0);
  EXPECT_EQ(tools[1].WiredPort, 101);
  EXPECT_EQ(tools[2].WiredPort, 2);
  EXPECT_FALSE(tools[2].RomPath.empty());
  EXPECT_TRUE(RefusedMentions(c, "tool Odd", "PortName \"two\" is not a wired port number"));

  std::ostringstream check, checkErr;
  ASSERT_EQ(RunTrackCommand({"--plus-config", file, "--check"}, nullptr, check, checkErr), 0) << checkErr.str();
  EXPECT_NE(check.str().find("tool Probe -> ProbeToTracker: wired port 2 channel 1 (the SROM in the tool)"), std::string::npos)
      << check.str();

  // On the simulator the tools stand still 150 mm apart along x in the order of the file.
  std::ostringstream out, err;
  ASSERT_EQ(RunTrackCommand({"--plus-config", file, "--simulate", "--seconds", "1.5", "--serve", "0", "--json"}, nullptr, out, err), 0)
      << err.str();
  const auto doc = nlohmann::json::parse(out.str());
  std::map<std::string, double> x;
  for (const auto& t : doc["plusTransforms"]) {
    EXPECT_EQ(t["state"], "OK") << t.dump();
    EXPECT_GT(t["published"].get<int>(), 10) << t.dump();
    x[t["name"]] = t["position"][0].get<double>();
  }
  ASSERT_EQ(x.size(), 3u) << out.str();
  EXPECT_NEAR(x["NeedleToTracker"], -200.0, 0.5);
  EXPECT_NEAR(x["ProbeToTracker"], -50.0, 0.5);
  EXPECT_NEAR(x["PatchedToTracker"], 100.0, 0.5);

  // Aurora and Polaris in one file: the first tracker with tools by default, the other by its Id.
  std::ostringstream first, firstErr, optical, opticalErr, none, noneErr;
  ASSERT_EQ(RunTrackCommand({"--plus-config", kConfigs + "PlusDeviceSet_Server_NDIAurora_NDIPolaris.xml", "--check", "--json"},
                            nullptr, first, firstErr), 0);
  EXPECT_EQ(nlohmann::json::parse(first.str())["runs"], "EmTracker");
  ASSERT_EQ(RunTrackCommand({"--plus-config", kConfigs + "PlusDeviceSet_Server_NDIAurora_NDIPolaris.xml", "--plus-device",
                             "OpticalTracker", "--check", "--json"}, nullptr, optical, opticalErr), 0);
  const auto opticalDoc = nlohmann::json::parse(optical.str());
  EXPECT_EQ(opticalDoc["runs"], "OpticalTracker");
  EXPECT_NE(opticalDoc["refused"].dump().find("--plus-device EmTracker"), std::string::npos) << opticalDoc["refused"].dump();
  EXPECT_EQ(RunTrackCommand({"--plus-config", kConfigs + "PlusDeviceSet_Server_NDIAurora_NDIPolaris.xml", "--plus-device", "Nope",
                             "--check"}, nullptr, none, noneErr), 2);
  EXPECT_NE(noneErr.str().find("no NDI tracker with Id Nope"), std::string::npos) << noneErr.str();
}
