// The plan's virtual fixtures switched through vtkRPHapticsLogic::SetPlanFixtures while the 1 kHz
// servo runs (what the Haptics panel's Guidance group calls): the stylus held 1.5 mm beside a
// straight trajectory feels the axis guidance's spring k·d towards the axis (k as the device
// renders it) once the fade is over; with the depth stop on, the stylus pushed 2 mm past the
// target is held at the target depth (the tool point never passes it) with the wall's k·2 mm; all
// off, the force goes back to the contact force alone (none here). No switch changes the force by
// more than the device profile's MaxForceRate × period in one tick. A plan with nothing to guide
// by is refused with its reason, the fixtures in use kept. Headless (runs under TSan).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include <vtkMatrix4x4.h>

#include "rpFixtureSet.h"
#include "rpHapticSession.h"
#include "rpHapticsGuidanceScene.h"
#include "vtkRPHapticsLogic.h"

namespace {

void Pump(vtkRPHapticsLogic* logic, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    logic->Update();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

void Place(vtkRPHapticsLogic* logic, double r, double a, double s) {
  vtkNew<vtkMatrix4x4> pose;
  pose->SetElement(0, 3, r);
  pose->SetElement(1, 3, a);
  pose->SetElement(2, 3, s);
  logic->SetSimulatedStylusPose(pose);
}

// The latest tick that ran on time (a late tick's force is held to what the motion justifies:
// on a loaded machine the next one is read).
rp::HapticState State(vtkRPHapticsLogic* logic) {
  rp::HapticState s;
  for (int i = 0; i < 100; ++i) {
    EXPECT_TRUE(logic->GetSession()->Servo().ReadState(s));
    if (!s.StallLimited && s.RampScale >= 1) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return s;
}

}  // namespace

TEST(HapticsPlanFixtures, SwitchedWhileRunningClosedFormForcesAndBoundedSteps) {
  vtkNew<vtkRPScene> scene;
  rptest::AddGuidanceScene(scene);
  vtkNew<vtkRPHapticsLogic> logic;
  logic->SetScene(scene);
  std::filesystem::create_directories(ROBOPLAN_TEST_OUTPUT_DIR);
  const std::string log = std::string(ROBOPLAN_TEST_OUTPUT_DIR) + "/haptics-plan-fixtures.csv";
  logic->SetLogPath(log);
  logic->SetRampSeconds(0.05);
  const double d = 1.5;  // mm beside the axis, inside the 3 mm capture radius
  Place(logic, d, 0, -50);
  std::string error;
  ASSERT_TRUE(logic->StartSimulated(error)) << error;
  Pump(logic, 0.2);
  EXPECT_NEAR(rp::Norm(State(logic).Force), 0, 1e-12);  // no fixture, no contact
  EXPECT_EQ(State(logic).Fixtures.Count, 0);

  // Axis guidance on while running.
  rp::PlanFixtureChoice choice;
  choice.Axis = true;
  const double axisOn = State(logic).Time;
  ASSERT_TRUE(logic->SetPlanFixtures(choice, error)) << error;
  ASSERT_EQ(logic->GetPlanFixtures()->Count(), 1);
  Pump(logic, 0.3);
  rp::HapticSession* session = logic->GetSession();
  const rp::DeviceInfo& device = session->DeviceLimits();
  const double period = session->StabilityPeriod();
  const double k = rp::RenderedFixtureStiffness(choice.AxisTuning, device, period);
  rp::HapticState s = State(logic);
  EXPECT_NEAR(s.Force.x, -k * d, 1e-6 * k * d + 1e-9);
  EXPECT_NEAR(s.Force.y, 0, 1e-9);
  EXPECT_NEAR(s.Force.z, 0, 1e-9);
  ASSERT_EQ(s.Fixtures.Count, 1);
  EXPECT_TRUE(s.Fixtures.Fixtures[0].Engaged);
  EXPECT_NEAR(s.Fixtures.Fixtures[0].Distance, d, 1e-9);
  std::printf("axis guidance, stylus %.1f mm off: F = (%.4f, %.4f, %.4f) N, k = %.3f N/mm\n", d, s.Force.x, s.Force.y,
              s.Force.z, k);

  // Depth stop on, then the stylus pushed 2 mm past the target.
  choice.Depth = true;
  const double depthOn = State(logic).Time;
  ASSERT_TRUE(logic->SetPlanFixtures(choice, error)) << error;
  Pump(logic, 0.15);
  const double pushed = State(logic).Time;
  Place(logic, d, 0, rptest::TargetS - 2);
  Pump(logic, 0.3);
  s = State(logic);
  const double kDepth = rp::RenderedFixtureStiffness(choice.DepthTuning, device, period);
  EXPECT_NEAR(s.Hip.z, rptest::TargetS, 1e-6);  // the tool point, held at the target depth
  EXPECT_NEAR(s.Force.z, kDepth * 2, 1e-5);
  EXPECT_NEAR(s.Force.x, -k * d, 1e-6 * k * d);
  std::printf("depth stop, stylus 2 mm past the target: tool point S = %.4f (target %.1f), F = (%.4f, %.4f, %.4f) N\n",
              s.Hip.z, rptest::TargetS, s.Force.x, s.Force.y, s.Force.z);

  // A choice with nothing to act on is refused; the fixtures in use stay.
  rp::PlanFixtureChoice wrong = choice;
  wrong.Trajectory = "no such plan";
  EXPECT_FALSE(logic->SetPlanFixtures(wrong, error));
  EXPECT_NE(error.find("no trajectory 'no such plan'"), std::string::npos) << error;
  EXPECT_EQ(logic->GetPlanFixtures()->Count(), 2);

  // Everything off while pushed past the target: the force fades back to the contact force (none).
  const double off = State(logic).Time;
  ASSERT_TRUE(logic->SetPlanFixtures(rp::PlanFixtureChoice{}, error)) << error;
  EXPECT_EQ(logic->GetPlanFixtures()->Count(), 0);
  Pump(logic, 0.3);
  s = State(logic);
  EXPECT_NEAR(rp::Norm(s.Force), 0, 1e-9);
  EXPECT_NEAR(s.Hip.z, rptest::TargetS - 2, 1e-6);  // the tool point is the stylus again
  // The fades' budget per tick is MaxForceRate × the period the servo assumes: the measured p99
  // once it grew past the nominal one (a loaded machine), never less.
  const double lastPeriod = session->StabilityPeriod();
  logic->Stop();

  // Every tick of the run: the switches' steps within the device's event rate; the tool point
  // never past the target while the depth stop held it.
  const std::vector<rptest::LogRow> rows = rptest::ReadSessionLog(log);
  ASSERT_GT(rows.size(), 500u);
  const double limit = device.MaxForceRate * lastPeriod + 1e-4;  // the log's 5 decimals
  const double onStep = rptest::LargestStep(rows, axisOn, pushed - 0.01);
  const double offStep = rptest::LargestStep(rows, off, rows.back().Time);
  EXPECT_LE(onStep, limit);
  EXPECT_LE(offStep, limit);
  EXPECT_GT(onStep, 0.5 * device.MaxForceRate * period);  // the fade ran at the device's rate (k·d spans several ticks)
  double deepest = 0;
  for (const rptest::LogRow& r : rows)
    if (r.Time > depthOn && r.Time < off) deepest = std::fmin(deepest, r.Hip.z - rptest::TargetS);
  EXPECT_GE(deepest, -1e-4);
  std::printf("largest step: switching on %.4f N, off %.4f N (limit %.4f N/tick); deepest tool point %.5f mm past the target\n",
              onStep, offStep, device.MaxForceRate * lastPeriod, -deepest);
}
