// NDI driver against the Polaris simulator, over both links (parameterized): a pseudo-terminal
// (serial) and TCP on 127.0.0.1 (a Polaris Vega/Lyra): set-up (reset by break and by the RESET
// command), tool loading, tracking (BX and TX), occlusion, out of volume, a CRC fault, a
// dropped reply, unplug and replug.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <thread>

#include "rpNdiTracker.h"
#include "rpPolarisSimulator.h"
#include "rpToolDefinition.h"
#include "rpTrackingTestHelpers.h"

using namespace rp;
using test::FreePort;
using test::TestMatrix;
using test::WaitFor;

namespace {

std::string OutputDir() {
  const std::string dir = ROBOPLAN_TEST_OUTPUT_DIR;
  std::filesystem::create_directories(dir);
  return dir;
}

ToolDefinition Tool(const std::string& name) {
  return ReadToolDefinition(std::string(ROBOPLAN_RESOURCES_DIR) + "/Tools/" + name + ".json");
}

enum class Link { Serial, Tcp };

struct Rig {
  Rig(Link kind, const std::string& link, PolarisSimulator::Options options = {}, bool binary = true) : Kind(kind) {
    if (kind == Link::Tcp) options.TcpPort = 0;  // a free port on 127.0.0.1
    else options.LinkPath = OutputDir() + "/" + link;
    options.FrameRate = 60;
    Stylus = Tool("Stylus");
    Reference = Tool("Reference");
    Sim = std::make_unique<PolarisSimulator>(options);
    Sim->AddTool(Stylus);
    Sim->AddTool(Reference);
    std::string error;
    Started = Sim->Start(error);
    EXPECT_TRUE(Started) << error;
    NdiTracker::Options o;
    o.Port = Sim->PortPath();
    o.Tcp = kind == Link::Tcp;
    o.Tools = {{"Stylus", Stylus.Rom}, {"Reference", Reference.Rom}};
    o.Binary = binary;
    o.CommandTimeoutMs = 1000;
    o.TrackingTimeoutMs = 100;
    o.ReconnectInitialSeconds = 0.05;
    o.ReconnectMaxSeconds = 0.4;
    TrackerOptions = o;
  }
  void StartTracker() {
    Tracker = std::make_unique<NdiTracker>(TrackerOptions);
    Tracker->Start();
  }
  bool WaitTracking(double seconds = 5) {
    return WaitFor([&] { return Tracker->GetState() == NdiTracker::State::Tracking && Tracker->GetStatistics().Frames > 5; }, seconds);
  }
  ToolPose Newest(const char* name, uint64_t* count = nullptr) { return test::Newest(Tracker->Poses(), name, count); }
  ToolState NewestState(const char* name) { return Newest(name).State; }

  Link Kind;
  ToolDefinition Stylus, Reference;
  std::unique_ptr<PolarisSimulator> Sim;
  NdiTracker::Options TrackerOptions;
  std::unique_ptr<NdiTracker> Tracker;
  bool Started = false;
};

// Tip of the stylus in tracker coordinates from a tracked pose.
void TipPosition(const ToolPose& pose, const std::array<double, 3>& tip, double out[3]) {
  double m[16];
  pose.ToMatrix(m);
  for (int r = 0; r < 3; ++r) out[r] = m[4 * r] * tip[0] + m[4 * r + 1] * tip[1] + m[4 * r + 2] * tip[2] + m[4 * r + 3];
}

// The tracked pose is the simulator's true pose at t = 0 (a static tool), to BX's float precision.
void ExpectTruePose(const PolarisSimulator& sim, const std::string& tool, const ToolPose& pose) {
  double truth[16], got[16];
  sim.TruePose(tool, 0, truth);
  pose.ToMatrix(got);
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(got[i], truth[i], i % 4 == 3 ? 1e-3 : 1e-6) << tool << " " << i;
}

class NdiDriver : public ::testing::TestWithParam<Link> {
 protected:
  Link Kind() const { return this->GetParam(); }
  bool Serial() const { return this->GetParam() == Link::Serial; }
  /// A simulator on this test's link: a pty behind OutputDir()/name, or TCP on a free port.
  PolarisSimulator::Options LinkOptions(const std::string& name) const {
    PolarisSimulator::Options options;
    if (Serial()) options.LinkPath = OutputDir() + "/" + name;
    else options.TcpPort = 0;
    return options;
  }
  /// A driver for `sim` over this test's link, loading `tools`.
  NdiTracker::Options DriverFor(const PolarisSimulator& sim, std::vector<NdiTracker::Tool> tools) const {
    NdiTracker::Options o;
    o.Port = sim.PortPath();
    o.Tcp = !Serial();
    o.Tools = std::move(tools);
    o.CommandTimeoutMs = 1000;
    return o;
  }
};

}  // namespace

INSTANTIATE_TEST_SUITE_P(Links, NdiDriver, ::testing::Values(Link::Serial, Link::Tcp),
                         [](const ::testing::TestParamInfo<Link>& info) { return info.param == Link::Serial ? "Serial" : "Tcp"; });

TEST_P(NdiDriver, TracksSimulatedToolsWithBx) {
  Rig rig(Kind(), "bx");
  ASSERT_TRUE(rig.Started);
  rig.StartTracker();
  ASSERT_TRUE(rig.WaitTracking()) << rig.Tracker->LastError();
  const auto counters = rig.Sim->GetCounters();
  // Serial: the fastest COMM rate negotiated; TCP: no COMM at all (a socket has no baud rate).
  EXPECT_EQ(counters.Baud, Serial() ? 1228739 : 9600);
  EXPECT_EQ(counters.LoadedTools, 2);
  EXPECT_TRUE(counters.Tracking);
  EXPECT_EQ(rig.Tracker->NegotiatedBaud(), Serial() ? 1228739 : 9600);
  EXPECT_NE(rig.Tracker->FirmwareVersion().find("Polaris"), std::string::npos);

  // The static reference: exactly its scripted pose (float precision of BX).
  const ToolPose reference = rig.Newest("ReferenceToTracker");
  ASSERT_EQ(reference.State, ToolState::OK);
  ExpectTruePose(*rig.Sim, "Reference", reference);
  EXPECT_GT(reference.Error, 0.1);
  EXPECT_LT(reference.Error, 0.3);

  // The pivoting stylus keeps its tip on the pivot point in every frame.
  for (int k = 0; k < 5; ++k) {
    const ToolPose stylus = rig.Newest("StylusToTracker");
    ASSERT_EQ(stylus.State, ToolState::OK);
    double tip[3];
    TipPosition(stylus, rig.Stylus.TipOffset, tip);
    for (int r = 0; r < 3; ++r) EXPECT_NEAR(tip[r], rig.Stylus.Motion.Center[r], 0.01);
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
  }
  // Frame numbers advance at the camera rate (60 Hz) and polling keeps up: compared over the
  // time that really passed (a loaded machine may oversleep), within 100 ms of lag.
  const double t0 = SteadySeconds();
  const uint32_t f0 = rig.Newest("StylusToTracker").Frame;
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const uint32_t f1 = rig.Newest("StylusToTracker").Frame;
  EXPECT_NEAR(static_cast<double>(f1 - f0), 60.0 * (SteadySeconds() - t0), 6.0);
  rig.Tracker->Stop();
  EXPECT_EQ(rig.Tracker->GetState(), NdiTracker::State::Stopped);
  EXPECT_FALSE(rig.Sim->GetCounters().Tracking);  // TSTOP was sent
  EXPECT_EQ(rig.Sim->GetCounters().Baud, 9600);   // and COMM back to 9600
}

TEST_P(NdiDriver, TracksWithTextTxReplies) {
  Rig rig(Kind(), "tx", {}, /*binary=*/false);
  ASSERT_TRUE(rig.Started);
  rig.StartTracker();
  ASSERT_TRUE(rig.WaitTracking()) << rig.Tracker->LastError();
  const ToolPose stylus = rig.Newest("StylusToTracker");
  ASSERT_EQ(stylus.State, ToolState::OK);
  double tip[3];
  TipPosition(stylus, rig.Stylus.TipOffset, tip);
  // TX quantises the quaternion to 1e-4 (160 mm lever: ~0.05 mm) and positions to 0.01 mm.
  for (int r = 0; r < 3; ++r) EXPECT_NEAR(tip[r], rig.Stylus.Motion.Center[r], 0.1);
  EXPECT_EQ(rig.Tracker->GetStatistics().MalformedReplies, 0u);
}

TEST_P(NdiDriver, ResetByBreakWhenTheProbeFails) {
  Rig rig(Kind(), "break");
  ASSERT_TRUE(rig.Started);
  rig.Sim->DropNextReplies(1);  // the INIT probe goes unanswered (device at another baud)
  rig.StartTracker();
  ASSERT_TRUE(rig.WaitTracking()) << rig.Tracker->LastError();
  EXPECT_EQ(rig.Tracker->GetStatistics().Resets, 1u);
  // Serial: the break, delivered out of band (the .break socket), no RESET command needed.
  // TCP has no break: the RESET command does it.
  EXPECT_EQ(rig.Sim->GetCounters().Breaks, Serial() ? 1u : 0u);
  EXPECT_EQ(rig.Sim->GetCounters().Resets, Serial() ? 0u : 1u);
}

TEST_P(NdiDriver, ResetCommandWhenNoBreakArrives) {
  PolarisSimulator::Options options;
  options.AcceptBreak = false;
  Rig rig(Kind(), "nobreak", options);
  ASSERT_TRUE(rig.Started);
  rig.Sim->DropNextReplies(1);
  rig.StartTracker();
  ASSERT_TRUE(rig.WaitTracking(8)) << rig.Tracker->LastError();
  EXPECT_EQ(rig.Sim->GetCounters().Resets, 1u);
}

TEST_P(NdiDriver, OcclusionOutOfVolumeCrcFaultDroppedReply) {
  Rig rig(Kind(), "faults");
  ASSERT_TRUE(rig.Started);
  rig.StartTracker();
  ASSERT_TRUE(rig.WaitTracking()) << rig.Tracker->LastError();

  rig.Sim->SetOccluded("Stylus", true);
  EXPECT_TRUE(WaitFor([&] { return rig.NewestState("StylusToTracker") == ToolState::Missing; }, 1));
  EXPECT_EQ(rig.NewestState("ReferenceToTracker"), ToolState::OK);
  rig.Sim->SetOccluded("Stylus", false);
  EXPECT_TRUE(WaitFor([&] { return rig.NewestState("StylusToTracker") == ToolState::OK; }, 1));

  rig.Sim->SetOutOfVolume("Reference", true);
  EXPECT_TRUE(WaitFor([&] { return rig.NewestState("ReferenceToTracker") == ToolState::OutOfVolume; }, 1));
  rig.Sim->SetOutOfVolume("Reference", false);
  EXPECT_TRUE(WaitFor([&] { return rig.NewestState("ReferenceToTracker") == ToolState::OK; }, 1));

  const auto before = rig.Tracker->GetStatistics();
  rig.Sim->CorruptNextReplies(1);
  EXPECT_TRUE(WaitFor([&] { return rig.Tracker->GetStatistics().CrcErrors >= before.CrcErrors + 1; }, 1));
  EXPECT_EQ(rig.Tracker->GetStatistics().CrcErrors, before.CrcErrors + 1);  // only the injected one
  rig.Sim->DropNextReplies(1);
  // At least the dropped reply times out (a loaded machine may add late ones: not an error).
  EXPECT_TRUE(WaitFor([&] { return rig.Tracker->GetStatistics().Timeouts >= before.Timeouts + 1; }, 1));
  // The lost poll shows up as skipped camera frames, and tracking carries on.
  uint64_t n0 = 0, n1 = 0;
  rig.Newest("StylusToTracker", &n0);
  EXPECT_TRUE(WaitFor([&] { rig.Newest("StylusToTracker", &n1); return n1 > n0 + 10; }, 2));
  const auto after = rig.Tracker->GetStatistics();
  EXPECT_GE(after.FrameGaps, before.FrameGaps + 3);  // ~100 ms at 60 Hz went missing
  EXPECT_EQ(rig.Tracker->GetState(), NdiTracker::State::Tracking);
  EXPECT_EQ(after.Connections, 1u);
}

TEST_P(NdiDriver, UnplugAndReplugReconnects) {
  Rig rig(Kind(), "unplug");
  ASSERT_TRUE(rig.Started);
  rig.StartTracker();
  ASSERT_TRUE(rig.WaitTracking()) << rig.Tracker->LastError();
  rig.Sim->Unplug();
  EXPECT_TRUE(WaitFor([&] { return rig.Tracker->GetState() != NdiTracker::State::Tracking; }, 1));
  EXPECT_NE(rig.Tracker->LastError().find("unplugged"), std::string::npos) << rig.Tracker->LastError();
  // Another device appears meanwhile (in ctest -j2: another test's simulator). It gets the pty
  // number the unplugged one had; the driver, retrying its port, must not end up talking to it.
  PolarisSimulator::Options strangerOptions;
  PolarisSimulator stranger(strangerOptions);
  stranger.AddTool(rig.Stylus);
  std::string strangerError;
  ASSERT_TRUE(stranger.Start(strangerError)) << strangerError;
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // a few failed reconnects (back-off)
  EXPECT_EQ(stranger.GetCounters().Commands, 0u) << "the driver opened " << stranger.SlavePath();
  EXPECT_NE(rig.Tracker->LastError().find(Serial() ? "cannot open" : "cannot connect"), std::string::npos)
      << rig.Tracker->LastError();
  uint64_t before = 0;
  rig.Newest("StylusToTracker", &before);
  std::string error;
  ASSERT_TRUE(rig.Sim->Replug(error)) << error;
  EXPECT_TRUE(WaitFor([&] { return rig.Tracker->GetStatistics().Connections == 2; }, 5)) << rig.Tracker->LastError();
  uint64_t after = 0;
  EXPECT_TRUE(WaitFor([&] { rig.Newest("StylusToTracker", &after); return after > before + 10; }, 2));
  EXPECT_EQ(rig.Sim->GetCounters().LoadedTools, 2);  // tools loaded again on the new link
}

TEST_P(NdiDriver, BadRomAndBadPortGiveClearErrors) {
  Rig rig(Kind(), "badrom");
  ASSERT_TRUE(rig.Started);
  std::vector<uint8_t> garbage(752, 0x42);
  rig.TrackerOptions.Tools.push_back({"Broken", garbage});
  rig.StartTracker();
  ASSERT_TRUE(rig.WaitTracking()) << rig.Tracker->LastError();
  EXPECT_NE(rig.Tracker->LastError().find("Broken: not an NDI tool definition"), std::string::npos) << rig.Tracker->LastError();
  EXPECT_EQ(rig.NewestState("StylusToTracker"), ToolState::OK);

  NdiTracker::Options o;
  o.Tcp = !Serial();
  o.Port = Serial() ? OutputDir() + "/no-such-port" : "127.0.0.1:" + std::to_string(FreePort());  // nobody listens
  o.ReconnectInitialSeconds = 0.05;
  NdiTracker absent(o);
  absent.Start();
  EXPECT_TRUE(WaitFor([&] { return absent.GetState() == NdiTracker::State::Disconnected; }, 1));
  EXPECT_NE(absent.LastError().find(Serial() ? "cannot open" : "cannot connect"), std::string::npos) << absent.LastError();
  absent.Stop();
}

TEST_P(NdiDriver, SlowRepliesAreWaitedForOrTakenLate) {
  Rig rig(Kind(), "slow");
  ASSERT_TRUE(rig.Started);
  rig.StartTracker();
  ASSERT_TRUE(rig.WaitTracking()) << rig.Tracker->LastError();
  const auto before = rig.Tracker->GetStatistics();
  // Slower than usual but inside the 100 ms reply timeout: replies keep coming (timeouts only
  // when the machine adds more than 60 ms of its own).
  rig.Sim->SetReplyDelay(40);
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  const auto slow = rig.Tracker->GetStatistics();
  EXPECT_GT(slow.Frames, before.Frames + 4);
  // Slower than the timeout: polls time out and pile up in the device; once it is fast again
  // the backlog of late replies is taken (still valid data) before the next poll.
  rig.Sim->SetReplyDelay(130);
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  rig.Sim->SetReplyDelay(0);
  EXPECT_TRUE(WaitFor([&] { return rig.Tracker->GetStatistics().LateReplies >= 1; }, 3));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const auto after = rig.Tracker->GetStatistics();
  EXPECT_GT(after.Timeouts, slow.Timeouts);
  EXPECT_EQ(after.Connections, 1u);  // never lost the device
  EXPECT_EQ(rig.Tracker->GetState(), NdiTracker::State::Tracking);
  // Back in step: one reply per poll at the camera rate, over the time that really passed.
  uint64_t n0 = 0, n1 = 0;
  const double t0 = SteadySeconds();
  const uint32_t f0 = rig.Newest("StylusToTracker", &n0).Frame;
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const uint32_t f1 = rig.Newest("StylusToTracker", &n1).Frame;
  const double frames = 60.0 * (SteadySeconds() - t0);
  EXPECT_NEAR(static_cast<double>(f1 - f0), frames, 6.0);  // the newest pose is the camera's newest frame
  // One pose per poll, never more than the camera made; with both cores busy the poll thread is
  // scheduled late and a poll it misses is not made up (23 of 30 in a loaded suite run).
  EXPECT_LE(static_cast<double>(n1 - n0), frames + 6.0);
  EXPECT_GE(static_cast<double>(n1 - n0), 0.5 * frames);
}

TEST_P(NdiDriver, SimulatorTracksAToolFromARomItWasNotGiven) {
  // The camera knows no tools; the driver uploads a ROM (PVWR) it has never seen: the simulator
  // makes a tool of it, with the ROM's part number and markers, and tracks it standing still.
  PolarisSimulator sim(LinkOptions("romonly"));
  std::string error;
  ASSERT_TRUE(sim.Start(error)) << error;
  const std::vector<std::array<double, 3>> markers = {{0, 0, 0}, {0, 0, 50}, {0, 25, 100}, {0, -25, 135}};
  NdiTracker tracker(DriverFor(sim, {{"Probe", rom::Build("RP-PROBE-7", markers)}}));
  tracker.Start();
  ASSERT_TRUE(WaitFor([&] { return test::Newest(tracker.Poses(), "ProbeToTracker").State == ToolState::OK; }, 5))
      << tracker.LastError();
  EXPECT_EQ(sim.ToolNames(), std::vector<std::string>{"RP-PROBE-7"});
  const auto geometry = sim.ToolMarkers("RP-PROBE-7");
  ASSERT_EQ(geometry.size(), markers.size());
  for (size_t m = 0; m < markers.size(); ++m)
    for (size_t k = 0; k < 3; ++k) EXPECT_FLOAT_EQ(geometry[m][k], markers[m][k]);
  ExpectTruePose(sim, "RP-PROBE-7", test::Newest(tracker.Poses(), "ProbeToTracker"));
  tracker.Stop();
}

TEST_P(NdiDriver, SimulatorSeesOnlyToolsWhoseRomMarkersFaceTheCamera) {
  // With marker visibility on, the ROM's geometry decides: normals +z, a 90 degree maximum angle,
  // three markers needed. The same tool facing the camera is tracked, turned away it is MISSING.
  PolarisSimulator::Options options = LinkOptions("visibility");
  options.MarkerVisibility = true;
  PolarisSimulator sim(options);
  ToolDefinition facing;
  facing.Name = facing.PartNumber = "Facing";
  facing.Markers = {{0, 0, 0}, {0, 50, 0}, {40, 0, 0}, {-30, 70, 0}};
  facing.Rom = rom::Build(facing.PartNumber, facing.Markers);
  ToolDefinition away = facing;
  away.Name = away.PartNumber = "Away";
  away.Rom = rom::Build(away.PartNumber, away.Markers);
  away.Motion.Center[0] = 150;
  away.Motion.Euler[2] = 180;  // turned about x: the normals point away from the camera
  sim.AddTool(facing);
  sim.AddTool(away);
  std::string error;
  ASSERT_TRUE(sim.Start(error)) << error;
  NdiTracker tracker(DriverFor(sim, {{"Facing", facing.Rom}, {"Away", away.Rom}}));
  tracker.Start();
  ASSERT_TRUE(WaitFor([&] { return test::Newest(tracker.Poses(), "FacingToTracker").State == ToolState::OK; }, 5))
      << tracker.LastError();
  EXPECT_EQ(test::Newest(tracker.Poses(), "AwayToTracker").State, ToolState::Missing);
  tracker.Stop();
}

// Wired tools (Aurora sensors, Polaris active tools) are found by their port, as PLUS's PortName
// names it (channel * 100 + port - 1), their definitions read from the SROM in each tool; a
// passive tool beside them is loaded from its ROM; a port with nothing plugged in is named and
// the others track.
TEST_P(NdiDriver, FindsWiredToolsByTheirPortAsPlusNamesThem) {
  PolarisSimulator sim(LinkOptions("wired"));
  const ToolDefinition stylus = Tool("Stylus"), reference = Tool("Reference");
  ToolDefinition needle = Tool("Pointer");
  needle.Name = "Needle";
  needle.Motion.Type = ToolTrajectory::Static;
  needle.Motion.Center[0] = 120;
  needle.Motion.Center[1] = -40;
  sim.AddTool(reference);       // passive: the driver uploads its ROM
  sim.AddTool(stylus, 1);       // wired port 2
  sim.AddTool(needle, 100);     // wired port 1, channel 1 (a 5-DOF splitter's second sensor)
  std::string error;
  ASSERT_TRUE(sim.Start(error)) << error;
  NdiTracker tracker(DriverFor(sim, {{"Reference", reference.Rom}, {"Stylus", {}, 1}, {"Needle", {}, 100}, {"Empty", {}, 2}}));
  tracker.Start();
  ASSERT_TRUE(WaitFor([&] { return test::Newest(tracker.Poses(), "NeedleToTracker").State == ToolState::OK &&
                                   test::Newest(tracker.Poses(), "StylusToTracker").State == ToolState::OK &&
                                   test::Newest(tracker.Poses(), "ReferenceToTracker").State == ToolState::OK; }, 5))
      << tracker.LastError();
  EXPECT_EQ(sim.GetCounters().LoadedTools, 3);
  EXPECT_NE(tracker.LastError().find("Empty: no tool in wired port 3 (PortName 2)"), std::string::npos) << tracker.LastError();
  // Each name carries its own tool's pose: the needle where it stands, the stylus tip on its pivot.
  ExpectTruePose(sim, "Needle", test::Newest(tracker.Poses(), "NeedleToTracker"));
  double tip[3];
  TipPosition(test::Newest(tracker.Poses(), "StylusToTracker"), stylus.TipOffset, tip);
  for (int r = 0; r < 3; ++r) EXPECT_NEAR(tip[r], stylus.Motion.Center[r], 0.01);
  tracker.Stop();
}

// PLUS's PortName with a RomFile: the ROM goes over the wired tool's own SROM (a broken SROM's
// replacement), and the device tracks the tool the written definition describes.
TEST_P(NdiDriver, AVirtualSromWrittenOverAWiredPortDefinesItsTool) {
  PolarisSimulator sim(LinkOptions("virtual-srom"));
  const ToolDefinition stylus = Tool("Stylus"), reference = Tool("Reference");
  sim.AddTool(reference);   // known to the camera, never uploaded as a passive tool here
  sim.AddTool(stylus, 0);   // plugged into wired port 1
  std::string error;
  ASSERT_TRUE(sim.Start(error)) << error;
  NdiTracker tracker(DriverFor(sim, {{"Rewritten", reference.Rom, 0}}));
  tracker.Start();
  ASSERT_TRUE(WaitFor([&] { return test::Newest(tracker.Poses(), "RewrittenToTracker").State == ToolState::OK; }, 5))
      << tracker.LastError();
  ExpectTruePose(sim, "Reference", test::Newest(tracker.Poses(), "RewrittenToTracker"));
  tracker.Stop();
}
