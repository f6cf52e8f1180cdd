// Fault: the servo thread stalls for 20 ms while the stylus is in contact with bone (on this kind
// of machine the 1 kHz loop was measured up to 19.8 ms late). Known answers: the first force after
// the stall is no larger than the force before it plus the rendered stiffness times the distance
// the device really moved (the spring's own growth), never above the device's 3.3 N; the ticks
// after it grow by no more than k·|Δx| plus the damping budget times the real velocity (no kick:
// nothing is estimated over the stall); and the passivity observer's energy stays ≥ 0 (the
// environment absorbed energy, it injected none).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>
#include <vector>

#include "rpDeviceProfiles.h"
#include "rpHapticServo.h"
#include "rpHapticsTestScenes.h"
#include "rpSimulatedDevice.h"

using rp::Vec3;

namespace {

const rp::DeviceInfo& Omni() {
  static rp::DeviceInfo info = [] {
    rp::DeviceProfile p;
    std::string error;
    rp::FindDeviceProfile("omni", p, error);
    return p.Info;
  }();
  return info;
}

// Bone as the Omni renders it (the table's k through the device's limits at 1 kHz).
double RenderedBoneStiffness() {
  const rp::MaterialTable table = rp::MaterialTable::Defaults();
  const auto clamps = rp::ClampMaterials(table.Materials(), Omni(), 0.001);
  return clamps[static_cast<size_t>(table.Find("bone"))].RenderedStiffness;
}

std::unique_ptr<rp::HapticScene> BoneSlab() {
  return rptest::Scene({{"slab", "bone", rp::shapes::Box({-40, -40, -20}, {40, 40, 0})}}, rp::MaterialTable::Defaults());
}

// A vertical path through timed waypoints (z only).
std::shared_ptr<rp::WaypointTrajectory> Path(const std::vector<double>& t, const std::vector<double>& z) {
  std::vector<Vec3> p;
  for (double zi : z) p.push_back({0, 0, zi});
  auto path = std::make_shared<rp::WaypointTrajectory>();
  std::string error;
  EXPECT_TRUE(path->Set(t, p, error)) << error;
  return path;
}

struct Tick {
  double Time, Elapsed, Energy;
  Vec3 Hip, Force;
  int Contacts;
  bool StallLimited;
};

// What the stall tests assert at each stall (a tick more than 1.5 periods after the one before).
struct StallCheck {
  double ForceBefore = 0, ForceAfter = 0, Bound = 0, Move = 0, Elapsed = 0, WorstFollowingExcess = -1e9;
  double HipZBefore = 0, HipZAfter = 0;
};

// Damping the renderer may add at most: the material's plus the passivity controller's cap.
double DampingBudget() {
  const rp::MaterialTable table = rp::MaterialTable::Defaults();
  return table.Materials()[static_cast<size_t>(table.Find("bone"))].Damping + Omni().NominalMaxDamping;
}

// Stalls that begin inside the force ramp (`rampSeconds` from the first tick) are left out: the
// ramp scales the force after the stall more than the force before it, so the logged forces do
// not obey F_before + k·|Δx| there (the renderer's bound holds on the forces before the ramp).
std::vector<StallCheck> CheckStalls(const std::vector<Tick>& ticks, double k, double maxForce, double minStall,
                                    double rampSeconds = 0) {
  std::vector<StallCheck> checks;
  for (size_t i = 1; i < ticks.size(); ++i) {
    if (ticks[i].Elapsed < minStall || ticks[i - 1].Time < ticks.front().Time + rampSeconds) continue;
    StallCheck c;
    c.Elapsed = ticks[i].Elapsed;
    c.ForceBefore = rp::Norm(ticks[i - 1].Force);
    c.ForceAfter = rp::Norm(ticks[i].Force);
    c.Move = rp::Norm(ticks[i].Hip - ticks[i - 1].Hip);
    c.Bound = std::fmin(maxForce, c.ForceBefore + k * c.Move);
    c.HipZBefore = ticks[i - 1].Hip.z;
    c.HipZAfter = ticks[i].Hip.z;
    // The next 20 ticks: each grows by no more than the spring's own growth plus the damping
    // budget at the real velocity (1 mN of slack for the proxy's gap and rounding).
    for (size_t j = i + 1; j < std::min(ticks.size(), i + 21); ++j) {
      const double growth = rp::Norm(ticks[j].Force) - rp::Norm(ticks[j - 1].Force);
      const double move = rp::Norm(ticks[j].Hip - ticks[j - 1].Hip);
      const double allowed = k * move + DampingBudget() * move / ticks[j].Elapsed;
      c.WorstFollowingExcess = std::fmax(c.WorstFollowingExcess, growth - allowed);
    }
    checks.push_back(c);
  }
  return checks;
}

const char* Phase(const StallCheck& c) {
  if (c.HipZAfter < c.HipZBefore - 1e-3) return "pressing in";
  if (c.HipZAfter > c.HipZBefore + 1e-3) return "withdrawing";
  return "holding";
}

}  // namespace

// Deterministic: the servo task driven tick by tick, the clock jumping 21 ms at one tick.
TEST(ServoStall, TwentyMillisecondsWhilePressingIntoBoneGivesNoKick) {
  const double k = RenderedBoneStiffness();
  // z = +1 down to -3 mm at 50 mm/s: 1.5 mm deep at 50 ms, when the stall hits.
  rp::SimulatedDevice device(Omni());
  device.SetTrajectory(Path({0, 0.08}, {1, -3}));
  rp::HapticServo servo(device);
  servo.SetRampSeconds(0.01);
  servo.Scenes().Publish(BoneSlab());
  servo.EnableLog(true);
  servo.ServoStarted();
  rp::TickInfo tick;
  double now = 0;
  for (int i = 0; i < 100; ++i, ++tick.Index) {
    if (i == 51) {
      now += 0.020;  // the stall: 20 periods lost
      tick.Index += 20;
    }
    tick.Time = now;
    servo.Tick(tick);
    now += 1e-3;
  }
  std::vector<Tick> ticks;
  rp::HapticLogRecord r;
  while (servo.LogRing().TryPop(r))
    ticks.push_back({r.Time, r.Elapsed, r.ObservedEnergy, r.Hip, r.Force, r.Contacts, (r.Flags & 4u) != 0});
  ASSERT_EQ(ticks.size(), 100u);
  const auto checks = CheckStalls(ticks, k, Omni().MaxForce, 0.015);
  ASSERT_EQ(checks.size(), 1u);
  const StallCheck& c = checks[0];
  EXPECT_NEAR(c.Move, 0.021 * 50, 1e-6);  // the device really moved 1.05 mm during the stall
  EXPECT_GT(c.ForceAfter, c.ForceBefore);    // pressing on: the spring grew ...
  EXPECT_LE(c.ForceAfter, c.Bound + 1e-9);   // ... by no more than k·|Δx|
  EXPECT_LT(c.WorstFollowingExcess, 1e-3);
  // Damping estimated over the true 21 ms: b·v stays b·50 mm/s (0.05 N), not b·1.05 mm / 1 ms.
  const double spring = k * (-ticks[51].Hip.z + rp::GodObjectProxy::Gap);
  EXPECT_NEAR(c.ForceAfter, spring + 0.001 * 50, 2e-3);
  for (const Tick& t : ticks) EXPECT_GE(t.Energy, -1e-9) << "t = " << t.Time;
  std::printf("[stall] synthetic, pressing 50 mm/s: before %.3f N, after %.3f N, bound %.3f N (moved %.2f mm)\n",
              c.ForceBefore, c.ForceAfter, c.Bound, c.Move);
}

TEST(ServoStall, StallAtFirstContactIsHeldToTheSpringForce) {
  // Above the surface before the stall, 1 mm into bone after it: the damping term (b·v) alone
  // would make the first contact force k·depth + b·v; the stall rule keeps it at k·|Δx|.
  const double k = RenderedBoneStiffness();
  rp::SimulatedDevice device(Omni());
  device.SetTrajectory(Path({0, 0.2}, {2, -8}));  // 50 mm/s
  rp::HapticServo servo(device);
  servo.SetRampSeconds(0);
  servo.Scenes().Publish(BoneSlab());
  servo.ServoStarted();
  rp::TickInfo tick;
  rp::HapticState before, after;
  double now = 0;
  for (; now < 0.0395; now += 1e-3, ++tick.Index) {  // last tick at 39 ms: z = 0.05 mm, no contact
    tick.Time = now;
    servo.Tick(tick);
  }
  ASSERT_TRUE(servo.ReadState(before));
  ASSERT_EQ(before.Contacts, 0);
  tick.Time = before.Time + 0.021;  // z = -1.0 mm
  servo.Tick(tick);
  ASSERT_TRUE(servo.ReadState(after));
  ASSERT_EQ(after.Contacts, 1);
  const double move = rp::Norm(after.Hip - before.Hip);
  EXPECT_TRUE(after.StallLimited);
  EXPECT_LE(rp::Norm(after.Force), k * move + 1e-9);
  EXPECT_GE(rp::Norm(after.Force), k * (-after.Hip.z) - 1e-9);  // at least the spring itself
  EXPECT_NEAR(after.Elapsed, 0.021, 1e-12);
  EXPECT_EQ(after.Stalls, 1u);
}

// The real loop: ServoLoop::InjectStall makes its thread sleep 20 ms (as when the host does not
// run it) while pressing in, holding and withdrawing; every tick logged and checked.
TEST(ServoStall, InjectedStallsInTheRunningLoopWhilePressingHoldingWithdrawing) {
  const double k = RenderedBoneStiffness();
  rp::SimulatedDevice device(Omni());
  // Down 20 mm/s to 3 mm deep, hold 0.3 s, up at 20 mm/s.
  device.SetTrajectory(Path({0, 0.2, 0.5, 0.7, 0.8}, {1, -3, -3, 1, 1}));
  rp::HapticServo servo(device);
  servo.SetRampSeconds(0.05);
  servo.Scenes().Publish(BoneSlab());
  servo.EnableLog(true);
  rp::ServoLoop loop;
  rp::ServoLoop::Options options;
  options.SpinUs = 100;
  std::string error;
  ASSERT_TRUE(loop.Start(&servo, options, error)) << error;
  // Inject once the servo's clock passes each phase's start (polling at ~0.5 ms; on a loaded
  // host the stall may land later in the phase, the rules checked below hold anywhere).
  auto waitUntil = [&](double time) {
    rp::HapticState s;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (std::chrono::steady_clock::now() < deadline) {
      if (servo.ReadState(s) && s.Time > time) return;
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
  };
  for (double phase : {0.1, 0.3, 0.55}) {  // pressing in, holding, withdrawing
    waitUntil(phase);
    loop.InjectStall(0.020);
  }
  waitUntil(0.85);
  loop.Stop();

  std::vector<Tick> ticks;
  rp::HapticLogRecord r;
  while (servo.LogRing().TryPop(r))
    ticks.push_back({r.Time, r.Elapsed, r.ObservedEnergy, r.Hip, r.Force, r.Contacts, (r.Flags & 4u) != 0});
  ASSERT_GT(ticks.size(), 300u);
  EXPECT_EQ(servo.LogRing().DroppedCount(), 0u);
  // Every stall (injected ones are ≥ 20 ms; a loaded host adds its own): the rules hold.
  const auto checks = CheckStalls(ticks, k, Omni().MaxForce, 0.0015, 0.05);
  int injected = 0;
  double longest = 0;
  for (const StallCheck& c : checks) {
    EXPECT_LE(c.ForceAfter, c.Bound + 1e-9) << Phase(c) << " stall of " << c.Elapsed * 1e3 << " ms";
    EXPECT_LT(c.WorstFollowingExcess, 1e-3) << Phase(c) << " stall of " << c.Elapsed * 1e3 << " ms";
    longest = std::fmax(longest, c.Elapsed);
    if (c.Elapsed < 0.019) continue;
    ++injected;
    std::printf("[stall] %.1f ms while %s at z %.2f -> %.2f mm: force before %.3f N, after %.3f N, bound "
                "F_before + k|dx| = %.3f N\n",
                c.Elapsed * 1e3, Phase(c), c.HipZBefore, c.HipZAfter, c.ForceBefore, c.ForceAfter, c.Bound);
  }
  EXPECT_GE(injected, 3);
  // The passivity observer: no energy injected in any contact episode. (A stall far longer than
  // the injected ones while withdrawing more than half the depth would inject up to k·Δx²/2 —
  // the hand then feels the stale force, which no software can take back — and the passivity
  // controller dissipates it; the loaded host has not stalled that long here if longest < 40 ms.)
  double minEnergy = 0;
  for (const Tick& t : ticks) minEnergy = std::fmin(minEnergy, t.Energy);
  if (longest < 0.040) {
    EXPECT_GE(minEnergy, -1e-9);
  }
  double maxForce = 0;
  for (const Tick& t : ticks) maxForce = std::fmax(maxForce, rp::Norm(t.Force));
  EXPECT_LE(maxForce, Omni().MaxForce + 1e-9);
  std::printf("[stall] %zu ticks, %zu stalls (longest %.1f ms), minimum observed energy %.3g mJ, max force %.3f N\n",
              ticks.size(), checks.size(), longest * 1e3, minEnergy, maxForce);
}
