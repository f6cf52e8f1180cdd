// The pose-source interface: the registry (every kind, clear errors for bad configurations), a
// new kind added by one class and one registration line and used by `roboplan track` and the
// logic untouched, `track --json` counting OK / MISSING / out-of-volume frames, the image
// hand-over (triple buffer) between two threads, and the thread shell.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include "rpImageTable.h"
#include "rpPoseSource.h"
#include "rpTrackingCommands.h"
#include "rpTrackingRecording.h"
#include "rpTrackingTestHelpers.h"
#include "rpWorkerThread.h"
#include "vtkRPScene.h"
#include "vtkRPTrackedToolNode.h"
#include "vtkRPTrackingLogic.h"

using namespace rp;
using test::WaitFor;

namespace {

std::string OutputDir() {
  std::filesystem::create_directories(ROBOPLAN_TEST_OUTPUT_DIR);
  return ROBOPLAN_TEST_OUTPUT_DIR;
}

// A tracker vendor added the way the registry asks: one class ...
class ScriptedSource : public PoseSource {
 public:
  explicit ScriptedSource(int tools) : Tools(tools) {
    for (int t = 0; t < tools; ++t) this->Table.FindOrAdd(("Tool" + std::to_string(t) + "ToTracker").c_str());
  }
  ~ScriptedSource() override { this->Stop(); }
  static std::unique_ptr<PoseSource> Create(const PoseSourceConfig& config) {
    const double tools = config.Number("tools", 2);
    if (tools < 1 || tools > 8) throw std::invalid_argument("tools must be 1..8");
    return std::make_unique<ScriptedSource>(static_cast<int>(tools));
  }
  bool Start(std::string&) override {
    this->Worker.Start([this] {
      for (uint32_t frame = 1; this->Worker.Sleep(0.01); ++frame) {
        for (int t = 0; t < this->Tools; ++t) {
          ToolPose p;
          p.State = ToolState::OK;
          p.Translation[0] = t;
          p.Translation[1] = frame;
          p.Frame = frame;
          p.ReceiveTime = SteadySeconds();
          this->Table.Publish(t, p);
        }
        this->Ready.Notify();
      }
    });
    return true;
  }
  void Stop() override { this->Worker.Stop(); }
  const ToolPoseTable& Poses() const override { return this->Table; }
  bool Connected() const override { return this->Worker.Running(); }
  std::string StatusText() const override { return "scripted"; }
  nlohmann::json StatisticsJson() const override { return {{"tools", this->Tools}}; }

 private:
  int Tools;
  ToolPoseTable Table;
  WorkerThread Worker;
};
// ... and one registration, by its owner at start-up (here the test program's; a module's
// own kinds are one line in rpPoseSourceKinds.cxx).
const bool scriptedRegistered =
    rp::PoseSourceRegistry::Register({"scripted", "a scripted test tracker", "", ScriptedSource::Create});

}  // namespace

TEST(PoseSource, RegistryKnowsEveryKindAndNamesBadConfigurations) {
  std::vector<std::string> kinds;
  for (const auto& e : PoseSourceRegistry::Entries()) kinds.push_back(e.Kind);
  for (const char* kind : {"igtl", "replay", "serial", "simulator", "scripted"})
    EXPECT_NE(std::find(kinds.begin(), kinds.end(), kind), kinds.end()) << kind;

  auto failure = [](PoseSourceConfig c) -> std::string {
    try {
      PoseSourceRegistry::Create(c);
    } catch (const std::invalid_argument& e) {
      return std::string("invalid: ") + e.what();
    } catch (const std::exception& e) {
      return std::string("failed: ") + e.what();
    }
    return "created";
  };
  PoseSourceConfig c;
  c.Kind = "polhemus";
  EXPECT_NE(failure(c).find("invalid: no pose source of kind 'polhemus' (known: igtl, replay"), std::string::npos) << failure(c);
  c = {};
  c.Kind = "igtl";
  c.Address = "localhost";
  EXPECT_EQ(failure(c), "invalid: expected HOST:PORT, got 'localhost'");
  c.Address = "localhost:18944";
  c.Options["header-version"] = "3";
  EXPECT_EQ(failure(c), "invalid: header-version must be 1 or 2");
  c = {};
  c.Kind = "serial";
  c.Address = "/dev/ttyUSB0";
  EXPECT_NE(failure(c).find("invalid: give at least one tool definition"), std::string::npos);
  c.ToolFiles = {OutputDir() + "/missing.rom"};
  EXPECT_NE(failure(c).find("failed: "), std::string::npos) << failure(c);
  EXPECT_NE(failure(c).find("missing.rom"), std::string::npos) << failure(c);
  c = {};
  c.Kind = "replay";
  c.Address = OutputDir() + "/no-such-recording.txt";
  EXPECT_NE(failure(c).find("failed: cannot open recording"), std::string::npos) << failure(c);
  c = {};
  c.Kind = "simulator";
  c.Options["rate"] = "45";
  EXPECT_EQ(failure(c), "invalid: rate must be 20, 30 or 60 (Hz)");
  c.Options["rate"] = "fast";
  EXPECT_EQ(failure(c), "invalid: rate must be a number, got 'fast'");
}

TEST(PoseSource, ANewKindWorksInTheLogicAndTheCommandWithoutOtherChanges) {
  vtkNew<vtkRPScene> scene;
  vtkNew<vtkRPTrackingLogic> logic;
  logic->SetScene(scene);
  PoseSourceConfig config;
  config.Kind = "scripted";
  config.Options["tools"] = "3";
  std::string error;
  const int id = logic->Connect(config, error);
  ASSERT_GE(id, 0) << error;
  ASSERT_EQ(logic->GetReadyFds().size(), 1u);
  ASSERT_TRUE(WaitFor([&] {
    logic->UpdateNodes(SteadySeconds());
    return vtkRPTrackedToolNode::SafeDownCast(scene->GetFirstNodeByName("Tool2ToTracker")) != nullptr;
  }, 2));
  auto* node = vtkRPTrackedToolNode::SafeDownCast(scene->GetFirstNodeByName("Tool2ToTracker"));
  EXPECT_EQ(node->GetStatus(), vtkRPTrackedToolNode::StatusOK);
  EXPECT_DOUBLE_EQ(node->GetMatrixTransformToParent()->GetElement(0, 3), 2.0);
  EXPECT_EQ(logic->GetSource(id)->StatisticsJson()["tools"], 3);
  logic->RemoveSource(id);

  std::ostringstream out, err;
  ASSERT_EQ(RunTrackCommand({"--source", "scripted", "--option", "tools=2", "--seconds", "0.5", "--json"}, nullptr, out, err), 0)
      << err.str();
  const auto doc = nlohmann::json::parse(out.str());
  EXPECT_EQ(doc["source"], "scripted");
  ASSERT_EQ(doc["tools"].size(), 2u);
  EXPECT_EQ(doc["tools"][1]["name"], "Tool1ToTracker");
  EXPECT_GT(doc["tools"][1]["frames"]["ok"].get<int>(), 20);  // 100 Hz for 0.5 s
  EXPECT_EQ(doc["tools"][1]["lastPose"]["position"][0], 1.0);
}

// "received" counts the frames that carry a pose; MISSING frames are counted apart.
TEST(PoseSource, TrackJsonCountsFramesByStateAndGivesTheLastPose) {
  Recording recording;
  recording.Tools = {"Stylus"};  // as a serial session records it: replayed as StylusToTracker
  const ToolState pattern[] = {ToolState::OK, ToolState::OK, ToolState::Missing, ToolState::OK, ToolState::OutOfVolume};
  double lastX = 0;
  for (int i = 0; i < 30; ++i) {
    Recording::Sample s;
    s.Time = 0.01 * i;
    s.Pose.State = pattern[i % 5];
    if (s.Pose.State != ToolState::Missing) {
      s.Pose.Translation[0] = lastX = 10.0 + i;
      s.Pose.Translation[2] = -1500;
      s.Pose.Quaternion[0] = std::cos(0.1 * i);
      s.Pose.Quaternion[3] = std::sin(0.1 * i);
    }
    s.Pose.Frame = static_cast<uint32_t>(i + 1);
    recording.Samples.push_back(s);
  }
  const std::string file = OutputDir() + "/states.txt";
  recording.Write(file);
  std::ostringstream out, err;
  ASSERT_EQ(RunTrackCommand({"--replay", file, "--seconds", "1", "--stale", "5", "--json"}, nullptr, out, err), 0) << err.str();
  const auto doc = nlohmann::json::parse(out.str());
  ASSERT_EQ(doc["tools"].size(), 1u);
  const auto& tool = doc["tools"][0];
  EXPECT_EQ(tool["name"], "StylusToTracker");
  EXPECT_EQ(tool["frames"]["ok"], 18);
  EXPECT_EQ(tool["frames"]["missing"], 6);
  EXPECT_EQ(tool["frames"]["outOfVolume"], 6);
  EXPECT_EQ(tool["received"], 24);
  EXPECT_EQ(tool["status"], "OUT_OF_VOLUME");  // the last frame (29: pattern[4])
  const auto& pose = tool["lastPose"];
  EXPECT_EQ(pose["state"], "OUT_OF_VOLUME");
  EXPECT_DOUBLE_EQ(pose["position"][0].get<double>(), lastX);
  EXPECT_NEAR(pose["quaternion"][0].get<double>(), std::cos(2.9), 1e-6);  // w of sample 29
  EXPECT_NEAR(pose["matrix"][3].get<double>(), lastX, 1e-9);
  EXPECT_NEAR(pose["matrix"][11].get<double>(), -1500, 1e-9);
  EXPECT_GT(tool["rateHz"].get<double>(), 0);
  EXPECT_GE(tool["latencyMs"].get<double>(), 0);
}

// Frames of an image stream cross from a writer thread to a reader whole: never a frame that is
// half written, never an older frame after a newer one (run under ThreadSanitizer too).
TEST(PoseSource, ImageFramesCrossThreadsWholeAndInOrder) {
  ImageTable table;
  const int slot = table.FindOrAdd("US", 2);
  ASSERT_EQ(slot, 0);
  constexpr int kFrames = 2000;
  std::atomic<bool> done{false};
  std::thread writer([&] {
    for (int f = 1; f <= kFrames; ++f) {
      ImageFrame& frame = table.BeginWrite(slot);
      frame.Dimensions[0] = 64;
      frame.Dimensions[1] = 48;
      frame.Dimensions[2] = 1;
      frame.ScalarType = ImageFrame::UInt16;
      frame.Pixels.resize(frame.ByteCount());
      auto* v = reinterpret_cast<uint16_t*>(frame.Pixels.data());
      for (size_t i = 0; i < frame.Pixels.size() / 2; ++i) v[i] = static_cast<uint16_t>(f);
      table.EndWrite(slot);
    }
    done = true;
  });
  int last = 0, taken = 0;
  uint64_t published = 0;
  while (!done || published < kFrames) {
    const ImageFrame* frame = table.TakeNewest(slot, &published);
    if (!frame) {
      if (done && published == kFrames && last == kFrames) break;
      std::this_thread::yield();
      continue;
    }
    const auto* v = reinterpret_cast<const uint16_t*>(frame->Pixels.data());
    const int f = v[0];
    for (size_t i = 0; i < frame->Pixels.size() / 2; ++i) ASSERT_EQ(v[i], f) << "a torn frame";
    EXPECT_GT(f, last);
    last = f;
    ++taken;
  }
  writer.join();
  if (const ImageFrame* frame = table.TakeNewest(slot, &published)) last = reinterpret_cast<const uint16_t*>(frame->Pixels.data())[0];
  EXPECT_EQ(last, kFrames);  // the newest always arrives
  EXPECT_EQ(published, static_cast<uint64_t>(kFrames));
  EXPECT_GT(taken, 0);
}

TEST(PoseSource, ThreadShellStopsASleepAtOnceAndBacksOff) {
  WorkerThread worker;
  std::atomic<bool> woke{false};
  worker.Start([&] {
    worker.Sleep(30);
    woke = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const double t0 = SteadySeconds();
  worker.Stop();
  EXPECT_TRUE(woke);
  EXPECT_LT(SteadySeconds() - t0, 1.0);
  EXPECT_FALSE(worker.Running());
  worker.Fail("boom");
  EXPECT_EQ(worker.LastError(), "boom");

  Backoff backoff(0.1, 0.5);
  EXPECT_DOUBLE_EQ(backoff.Next(), 0.1);
  EXPECT_DOUBLE_EQ(backoff.Next(), 0.2);
  EXPECT_DOUBLE_EQ(backoff.Next(), 0.4);
  EXPECT_DOUBLE_EQ(backoff.Next(), 0.5);
  backoff.Reset();
  EXPECT_DOUBLE_EQ(backoff.Next(), 0.1);
}
