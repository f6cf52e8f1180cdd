// The haptic servo task: no allocation on the hot path, watchdog, force ramp, scene swap while
// running, thread start/stop (run this one under ThreadSanitizer too), session log.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <thread>

#include "rpAllocationCounter.h"
#include "rpFixtureConstraint.h"
#include "rpHapticsTestScenes.h"
#include "rpPlanFixtures.h"
#include "rpServoLoadReport.h"
#include "rpSessionLog.h"
#include "rpSimulatedDevice.h"

using rp::Vec3;

namespace {
double BoneStiffness() {
  const rp::MaterialTable table = rp::MaterialTable::Defaults();
  return table.Materials()[static_cast<size_t>(table.Find("bone"))].Stiffness;
}
std::unique_ptr<rp::HapticScene> BoneSlab(double top = 0) {
  return rptest::Scene({{"slab", "bone", rp::shapes::Box({-40, -40, top - 20}, {40, 40, top})}},
                       rp::MaterialTable::Defaults());
}
// Down into the slab, a sideways sweep (friction), and back up, repeated.
std::shared_ptr<rp::WaypointTrajectory> Probe() {
  auto path = std::make_shared<rp::WaypointTrajectory>();
  std::string error;
  std::vector<double> t;
  std::vector<Vec3> p;
  for (int cycle = 0; cycle < 20; ++cycle) {
    const double t0 = cycle * 0.4;
    t.insert(t.end(), {t0, t0 + 0.1, t0 + 0.2, t0 + 0.3});
    p.insert(p.end(), {{0, 0, 5}, {0, 0, -1}, {10, 5, -1.5}, {10, 5, 5}});
  }
  EXPECT_TRUE(path->Set(t, p, error)) << error;
  return path;
}
// The servo's ticks given by hand at 1 kHz (tick i at i ms, from where the last run stopped), its
// state read after each run: the set-up the servo tests share.
struct HandTicks {
  rp::HapticServo& Servo;
  rp::TickInfo Tick;
  rp::HapticState State;
  explicit HandTicks(rp::HapticServo& servo) : Servo(servo) { servo.ServoStarted(); }
  const rp::HapticState& Run(int ticks) {
    for (int i = 0; i < ticks; ++i, ++this->Tick.Index) this->Step();
    this->Servo.ReadState(this->State);
    return this->State;
  }
  const rp::HapticState& RunTo(double seconds) {
    for (; this->Tick.Index * 1e-3 < seconds; ++this->Tick.Index) this->Step();
    this->Servo.ReadState(this->State);
    return this->State;
  }
  void Step() {
    this->Tick.Time = this->Tick.Index * 1e-3;
    this->Servo.Tick(this->Tick);
  }
};
void Configure(rp::HapticServo& servo) {
  const Vec3 points[3] = {{0, 0, 0}, {0, 0, 15}, {0, 0, 30}};
  servo.Renderer().SetToolPoints(points, 3);
  servo.SetRampSeconds(0.05);
}
}  // namespace

TEST(HapticServo, TickDoesNotAllocate) {
  rp::SimulatedDevice device;
  device.SetTrajectory(Probe());
  rp::HapticServo servo(device);
  Configure(servo);
  servo.EnableLog(true);
  servo.Scenes().Publish(BoneSlab());
  rp::TickInfo tick;
  servo.ServoStarted();
  // Warm up (first contact, first scene acquisition), then count.
  for (int i = 0; i < 10; ++i, ++tick.Index) {
    tick.Time = tick.Index * 1e-3;
    servo.Tick(tick);
  }
  // A new scene arrives while running: swapping it in must not allocate or free either.
  servo.Scenes().Publish(BoneSlab(0.5));
  const uint64_t before = rp::alloc::ThreadAllocations();
  int contacts = 0;
  rp::HapticState state;
  for (int i = 0; i < 3000; ++i, ++tick.Index) {
    tick.Time = tick.Index * 1e-3;
    servo.Tick(tick);
    servo.ReadState(state);
    contacts += state.Contacts > 0;
  }
  EXPECT_EQ(rp::alloc::ThreadAllocations(), before);
  EXPECT_GT(contacts, 1000);  // the hot path really rendered contacts
  rp::HapticLogRecord r;
  int records = 0;
  while (servo.LogRing().TryPop(r)) ++records;
  EXPECT_GT(records, 3000);
}

TEST(HapticServo, ForceRampsInAndWatchdogZeroesIt) {
  rp::SimulatedDevice device;
  // Hold the stylus 1 mm inside the slab from the start.
  device.SetTrajectory(rp::WaypointTrajectory::Line({0, 0, 5}, {0, 0, -1}, 1000.0));
  rp::HapticServo servo(device);
  servo.SetRampSeconds(0.1);
  rp::RendererOptions o;
  o.PassivityControl = false;
  servo.Renderer().SetOptions(o);
  servo.Scenes().Publish(BoneSlab());
  HandTicks ticks(servo);
  rp::TickInfo& tick = ticks.Tick;
  const rp::HapticState& s = ticks.State;
  auto run = [&](int n) { ticks.Run(n); };
  run(51);  // t = 0.05 s: half the ramp
  const double full = BoneStiffness() * (1 + rp::GodObjectProxy::Gap);  // within the Omni's limits
  EXPECT_NEAR(s.RampScale, 0.5, 1e-9);
  EXPECT_NEAR(s.Force.z, 0.5 * full, 1e-6);
  run(100);
  EXPECT_NEAR(s.Force.z, full, 1e-6);
  EXPECT_NEAR(device.LastForce().z, full, 1e-6);
  // A device error: force zero at once, trip counted.
  device.InjectFault(true);
  run(1);
  EXPECT_TRUE(s.DeviceError);
  EXPECT_EQ(s.WatchdogTrips, 1u);
  EXPECT_EQ(rp::Norm(device.LastForce()), 0.0);
  device.InjectFault(false);
  run(1);
  EXPECT_LT(s.Force.z, 0.05 * full);  // ramps in again
  // An overrun tick: same.
  tick.PreviousOverran = true;
  run(1);
  tick.PreviousOverran = false;
  EXPECT_EQ(s.WatchdogTrips, 2u);
  EXPECT_EQ(rp::Norm(device.LastForce()), 0.0);
  run(200);
  EXPECT_NEAR(s.Force.z, full, 1e-6);
}

TEST(HapticServo, DeviceToSceneTransformAndWorkspaceScale) {
  rp::SimulatedDevice device;
  device.SetTrajectory(rp::WaypointTrajectory::Line({0, 0, 10}, {0, 0, 1}, 1000.0));
  rp::HapticServo servo(device);
  servo.SetRampSeconds(0);
  rp::RendererOptions o;
  o.PassivityControl = false;
  o.LimitGains = false;
  servo.Renderer().SetOptions(o);
  servo.Scenes().Publish(BoneSlab(100));  // slab top at z = 100 in RAS
  // RAS = Rx(90°)·(2·device) + (0,0,100): device (x,y,z) -> RAS (2x, -2z, 2y + 100).
  rp::DeviceToScene xf;
  xf.Scale = 2;
  const double r[9] = {1, 0, 0, 0, 0, -1, 0, 1, 0};
  std::copy(r, r + 9, xf.DeviceToRAS.R);
  xf.DeviceToRAS.T = {0, 0, 100};
  servo.Input().SetDeviceToScene(xf);
  servo.ServoStarted();
  rp::TickInfo tick;
  for (int i = 0; i < 50; ++i, ++tick.Index) {
    tick.Time = tick.Index * 1e-3;
    servo.Tick(tick);
  }
  rp::HapticState s;
  ASSERT_TRUE(servo.ReadState(s));
  // Device (0,0,1) -> scaled (0,0,2) -> rotated (0,-2,0) -> (0,-2,100): on the slab's top
  // plane z = 100, not inside: no contact.
  EXPECT_NEAR(s.Hip.y, -2.0, 1e-9);
  EXPECT_NEAR(s.Hip.z, 100.0, 1e-9);
  // Now device y = -0.5 (RAS z = 100 - 2 * 0.5): 1 mm deep; RAS +z is device +y.
  device.SetTrajectory(nullptr);
  rp::Pose manual;
  manual.T = {0, -0.5, 0};
  device.SetManualPose(manual);
  for (int i = 0; i < 100; ++i, ++tick.Index) {
    tick.Time = tick.Index * 1e-3;
    servo.Tick(tick);
  }
  ASSERT_TRUE(servo.ReadState(s));
  EXPECT_NEAR(s.Hip.z, 99.0, 1e-9);
  ASSERT_EQ(s.Contacts, 1);
  EXPECT_NEAR(s.Force.z, BoneStiffness() * (1 + rp::GodObjectProxy::Gap), 1e-6);
  EXPECT_NEAR(device.LastForce().y, s.Force.z, 1e-9);
  EXPECT_NEAR(device.LastForce().z, 0.0, 1e-9);
}

TEST(ToolInput, APoseInTheSceneIsTakenAsItIsWithTheDevicesWorkspaceScale) {
  // A tracked stylus, the viewer's spin boxes or a script in RAS: the pose reaches the renderer
  // unchanged (no trip to device coordinates and back), the force goes back in RAS, and the
  // scene's HapticDeviceToRAS only gives the scale of the device it stands for (gain limits).
  rp::SimulatedDevice device;
  rp::HapticServo servo(device);
  servo.SetRampSeconds(0);
  rp::RendererOptions o;
  o.PassivityControl = false;
  o.ForceShading = false;  // the box's corner normals would tilt the force off the face's normal
  servo.Renderer().SetOptions(o);
  servo.Scenes().Publish(BoneSlab(100));
  rp::DeviceToScene xf;
  xf.Scale = 2;
  const double r[9] = {1, 0, 0, 0, 0, -1, 0, 1, 0};
  std::copy(r, r + 9, xf.DeviceToRAS.R);
  xf.DeviceToRAS.T = {0, 0, 100};
  servo.Input().SetDeviceToScene(xf);
  servo.Input().SetPosesInScene(true);
  rp::Pose stylus;  // RAS: 1 mm into the slab, the stylus tilted 30° about A
  const double c = std::cos(M_PI / 6), sn = std::sin(M_PI / 6);
  const double tilt[9] = {c, 0, sn, 0, 1, 0, -sn, 0, c};
  std::copy(tilt, tilt + 9, stylus.R);
  stylus.T = {3, 4, 110};
  device.SetManualPose(stylus);
  servo.ServoStarted();
  rp::TickInfo tick;
  for (int i = 0; i < 20; ++i, ++tick.Index) {
    tick.Time = tick.Index * 1e-3;
    servo.Tick(tick);
  }
  stylus.T = {3, 4, 99};
  device.SetManualPose(stylus);
  for (int i = 0; i < 100; ++i, ++tick.Index) {
    tick.Time = tick.Index * 1e-3;
    servo.Tick(tick);
  }
  rp::HapticState s;
  ASSERT_TRUE(servo.ReadState(s));
  EXPECT_EQ(s.Hip.x, 3.0);
  EXPECT_EQ(s.Hip.y, 4.0);
  EXPECT_EQ(s.Hip.z, 99.0);
  for (int k = 0; k < 9; ++k) EXPECT_EQ(s.Stylus.R[k], tilt[k]) << k;
  ASSERT_EQ(s.Contacts, 1);
  // The Omni's nominal maximum (0.7 N/mm) bounds the bone's stiffness felt through the 2x scale.
  const rp::DeviceInfo omni = rp::SimulatedDevice::DefaultInfo();
  const double k = std::min(BoneStiffness() * 2, omni.NominalMaxStiffness) / 2;
  EXPECT_NEAR(s.Force.z, k * (1 + rp::GodObjectProxy::Gap), 1e-6);
  EXPECT_EQ(device.LastForce().z, s.Force.z);  // in RAS, not rotated into the device's frame
  EXPECT_EQ(device.LastForce().y, 0.0);
}

namespace {
// A one-sided wall z >= Top held by a spring k (a depth stop's simplest form), counting how it is
// carried over when a new set replaces its set.
class WallConstraint : public rp::ToolConstraint {
 public:
  WallConstraint(double top, double k) : Top(top), K(k) {}
  void Evaluate(const rp::ConstraintContext& tool, rp::ConstraintForce& out) noexcept override {
    const double depth = this->Top - tool.Tip.z;
    ++this->Evaluations;
    if (depth <= 0) return;
    out.Force += Vec3{0, 0, this->K * depth};
    out.Stiffness += this->K;
    out.StoredEnergy += 0.5 * this->K * depth * depth;
    out.Engaged = true;
  }
  void CarryFrom(const rp::ToolConstraint& previous) noexcept override {
    this->Evaluations = static_cast<const WallConstraint&>(previous).Evaluations;
    this->Carried = true;
  }
  double Top, K;
  int Evaluations = 0;
  bool Carried = false;
};
std::unique_ptr<rp::ToolConstraints> Wall(double top, double k, WallConstraint** wall = nullptr) {
  auto set = std::make_unique<rp::ToolConstraints>();
  auto constraint = std::make_unique<WallConstraint>(top, k);
  if (wall) *wall = constraint.get();
  set->Add(std::move(constraint));
  return set;
}
}  // namespace

TEST(HapticServo, AFixtureActsBesideTheContactsInsideThePassivityObserverAndTheClamp) {
  // No tissue anywhere: the wall alone pushes back, through the same observer and clamp.
  rp::SimulatedDevice device;
  device.SetTrajectory(rp::WaypointTrajectory::Line({0, 0, 5}, {0, 0, -1}, 10.0));
  rp::HapticServo servo(device);
  servo.SetRampSeconds(0);
  WallConstraint* wall = nullptr;
  servo.Constraints().Publish(Wall(0, 0.5, &wall));
  HandTicks ticks(servo);
  const rp::HapticState& s = ticks.State;
  auto run = [&](int n) { ticks.Run(n); };
  run(700);  // pressed 1 mm beyond the wall at 10 mm/s, then held
  EXPECT_EQ(s.Contacts, 0);
  EXPECT_NEAR(s.Force.z, 0.5, 1e-9);
  EXPECT_FALSE(s.Clamped);
  EXPECT_NE(s.ObservedEnergy, 0.0) << "the passivity observer ran over the fixture's episode";
  // A stiffer wall in its place: its state comes along, the force is clamped to the device's maximum.
  const int evaluated = wall->Evaluations;
  WallConstraint* stiff = nullptr;
  servo.Constraints().Publish(Wall(0, 10, &stiff));
  const uint64_t before = rp::alloc::ThreadAllocations();
  run(50);
  EXPECT_EQ(rp::alloc::ThreadAllocations(), before) << "swapping a fixture set in and evaluating it";
  servo.Constraints().Collect();
  EXPECT_TRUE(stiff->Carried);
  EXPECT_EQ(stiff->Evaluations, evaluated + 50);
  EXPECT_EQ(evaluated, 700);
  EXPECT_TRUE(s.Clamped);
  EXPECT_NEAR(rp::Norm(s.Force), rp::SimulatedDevice::DefaultInfo().MaxForce, 1e-9);
}

namespace {
// A plan as the Planning logic snapshots it: a trajectory down −S from the origin to 30 mm deep, and
// a vessel (a 4 mm sphere, margin 2 mm) 15 mm anterior of it at 20 mm depth.
std::shared_ptr<const rp::FixtureSet> PlanFixtures(double entryR = 0) {
  rp::PlanSnapshot plan;
  rp::TrajectorySnapshot t;
  t.NodeID = "vtkRPTrajectoryNode1";
  t.Name = "tunnel";
  t.Entry = {entryR, 0, 0};
  t.Target = {entryR, 0, -30};
  plan.Trajectories.push_back(t);
  rp::StructureAtRiskSnapshot vessel;
  vessel.NodeID = "vtkRPModelNode1";
  vessel.Name = "vessel";
  vessel.SafetyMarginMm = 2;
  auto field = std::make_shared<rp::MeshSignedDistance>();
  std::string error;
  EXPECT_TRUE(field->Build(rp::shapes::Sphere({0, 15, -20}, 4, 3), error)) << error;
  vessel.Signed = field;
  plan.StructuresAtRisk.push_back(vessel);
  rp::PlanFixtureChoice choice;
  EXPECT_TRUE(rp::ParseFixtureKinds("axis,depth,forbidden", choice, error)) << error;
  auto set = rp::BuildPlanFixtures(plan, choice, error);
  EXPECT_TRUE(set) << error;
  return set;
}
}  // namespace

// The plan's fixtures in the haptics servo, scripted ticks: a device held 1.5 mm beside the planned
// axis feels the axis guidance's spring on that distance, across the axis and nothing along it;
// pushed 1 mm past the target it also feels the depth stop's spring on that 1 mm; nothing allocates.
TEST(HapticServo, ThePlansFixturesGiveTheirClosedFormForcesAtOneKilohertz) {
  const auto fixtures = PlanFixtures();
  ASSERT_TRUE(fixtures && fixtures->Count() == 3);
  const double kAxis = fixtures->Entries[0].Tuning.Stiffness, kStop = fixtures->Entries[1].Tuning.Stiffness;
  rp::SimulatedDevice device;
  auto path = std::make_shared<rp::WaypointTrajectory>();
  std::string error;
  ASSERT_TRUE(path->Set({0, 1, 2, 2.5}, {{1.5, 0, 5}, {1.5, 0, -10}, {1.5, 0, -10}, {1.5, 0, -31}}, error)) << error;
  device.SetTrajectory(path);
  rp::HapticServo servo(device);
  servo.SetRampSeconds(0);
  servo.Constraints().Publish(rp::MakeFixtureConstraints(fixtures));
  HandTicks ticks(servo);
  const rp::HapticState& s = ticks.State;
  auto runTo = [&](double seconds) { ticks.RunTo(seconds); };
  runTo(1.9);  // held at 10 mm deep, 1.5 mm off the axis along R
  EXPECT_NEAR(s.Force.x, -kAxis * 1.5, 1e-6);
  EXPECT_NEAR(s.Force.y, 0, 1e-6);
  EXPECT_NEAR(s.Force.z, 0, 1e-6);
  const uint64_t before = rp::alloc::ThreadAllocations();
  runTo(3.5);  // down to 1 mm past the target, held
  EXPECT_EQ(rp::alloc::ThreadAllocations(), before) << "the servo's ticks with the plan's fixtures";
  EXPECT_NEAR(s.Force.x, -kAxis * 1.5, 1e-6);
  EXPECT_NEAR(s.Force.z, kStop * 1.0, 1e-6);
  EXPECT_FALSE(s.Clamped);
}

// The plan's fixtures in the servo's thread at 1 kHz while the main thread moves the plan (a new
// snapshot every display frame) and reads the state: the handover without locks (TSan runs this);
// the force stays within the device's maximum.
TEST(HapticServo, RunsThePlansFixturesInItsThreadWhileThePlanMoves) {
  rp::SimulatedDevice device;
  device.SetTrajectory(rp::WaypointTrajectory::Line({1, 0, 5}, {1, 0, -35}, 60.0));
  rp::HapticServo servo(device);
  servo.SetRampSeconds(0);
  servo.Constraints().Publish(rp::MakeFixtureConstraints(PlanFixtures()));
  rp::ServoLoop loop;
  std::string error;
  ASSERT_TRUE(loop.Start(&servo, rp::ServoLoop::Options{}, error)) << error;
  rp::HapticState s;
  double largest = 0;
  for (int frame = 0; frame < 12; ++frame) {  // ~30 Hz for 0.4 s
    std::this_thread::sleep_for(std::chrono::milliseconds(33));
    servo.Constraints().Publish(rp::MakeFixtureConstraints(PlanFixtures(0.1 * frame)));
    servo.Constraints().Collect();
    if (servo.ReadState(s)) largest = std::max(largest, rp::Norm(s.Force));
  }
  loop.Stop();
  EXPECT_GT(loop.Stats().Ticks, 200u);
  EXPECT_GT(largest, 0.1) << "the fixtures pushed";
  EXPECT_LE(largest, rp::SimulatedDevice::DefaultInfo().MaxForce + 1e-9);
  EXPECT_EQ(rp::Norm(device.LastForce()), 0.0);
}

TEST(HapticServo, RunsInItsThreadWhileTheMainThreadSwapsScenesAndReads) {
  rp::SimulatedDevice device;
  device.SetTrajectory(Probe());
  rp::HapticServo servo(device);
  Configure(servo);
  servo.EnableLog(true);
  servo.Scenes().Publish(BoneSlab());
  const std::string dir = ROBOPLAN_TEST_OUTPUT_DIR;
  ASSERT_EQ(std::system(("mkdir -p '" + dir + "'").c_str()), 0);
  rp::SessionLogWriter writer;
  std::string error;
  std::vector<std::string> names;
  const rp::MaterialTable table = rp::MaterialTable::Defaults();
  for (const auto& m : table.Materials()) names.push_back(m.Tissue);
  ASSERT_TRUE(writer.Start(servo.LogRing(), dir + "/session.csv", names, error)) << error;

  rp::ServoLoop loop;
  ASSERT_TRUE(loop.Start(&servo, rp::ServoLoop::Options{}, error)) << error;
  rp::HapticState s;
  int contactsSeen = 0;
  for (int frame = 0; frame < 15; ++frame) {  // ~30 Hz "display" for 0.5 s
    std::this_thread::sleep_for(std::chrono::milliseconds(33));
    if (servo.ReadState(s) && s.Contacts > 0) ++contactsSeen;
    if (frame % 5 == 4) servo.Scenes().Publish(BoneSlab(frame * 0.01));
    servo.Scenes().Collect();
  }
  loop.Stop();
  writer.Stop();
  const rp::ServoStats stats = loop.Stats();
  EXPECT_GT(stats.Ticks, 200u);
  EXPECT_GT(contactsSeen, 0);
  EXPECT_EQ(rp::Norm(device.LastForce()), 0.0);  // zero force after stop
  EXPECT_GE(writer.RecordsWritten() + servo.LogRing().DroppedCount(), stats.Ticks);
  std::ifstream log(dir + "/session.csv");
  std::string header, line;
  std::getline(log, header);
  EXPECT_EQ(header.rfind("time_s,hip_x", 0), 0u);
  int lines = 0, bone = 0;
  while (std::getline(log, line)) {
    ++lines;
    bone += line.find(",bone,") != std::string::npos;
  }
  EXPECT_EQ(static_cast<uint64_t>(lines), writer.RecordsWritten());
  EXPECT_GT(bone, 0);
}

// The reading names whose the misses were: the machine when it counted steal or preemption, RoboPlan
// when ticks overran, the host on a shielded CPU, and otherwise points at the tool that tells a host
// stall from another process holding interrupts off.
TEST(ServoLoadReading, NamesTheMachineRoboPlanOrTheHost) {
  rp::MachineLoad load;
  load.HasSteal = load.HasThread = true;
  EXPECT_EQ(rp::MachineLoadReading(load, 0, 0), "no misses");
  EXPECT_EQ(rp::MachineLoadReading(load, 3, 2).rfind("RoboPlan:", 0), 0u);
  const std::string unshielded = rp::MachineLoadReading(load, 3, 0);
  EXPECT_EQ(unshielded.rfind("the host or the timer:", 0), 0u) << unshielded;
  EXPECT_NE(unshielded.find("servo-wakeup-trace.py"), std::string::npos) << unshielded;
  load.Shielded = true;
  EXPECT_EQ(rp::MachineLoadReading(load, 3, 0).rfind("the host: woken late on a shielded CPU", 0), 0u);
  load.StealSeconds = 0.02;
  EXPECT_EQ(rp::MachineLoadReading(load, 3, 0).rfind("the machine: the hypervisor stole", 0), 0u);
}
