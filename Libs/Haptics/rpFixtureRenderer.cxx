#include "rpFixtureRenderer.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

namespace rp {

namespace {
bool SameTuning(const FixtureTuning& a, const FixtureTuning& b) {
  return a.Stiffness == b.Stiffness && a.Damping == b.Damping && a.Capture == b.Capture && a.Release == b.Release &&
         a.AngularStiffness == b.AngularStiffness;
}
constexpr int ConstrainRounds = 3;  // walls applied in turn until none moves the goal

// The springs act along (k·ddᵀ) or across (k·(I − ddᵀ)) their directions: what a device feels of
// them together is the largest eigenvalue of their sum (an axis guide across the axis and a depth
// stop along it are two orthogonal springs, not one of their summed stiffness).
struct StiffnessMatrix {
  Eigen::Matrix3d K = Eigen::Matrix3d::Zero();
  void Add(double k, const Vec3& d, bool across) noexcept {
    const Eigen::Vector3d u(d.x, d.y, d.z);
    const Eigen::Matrix3d along = u.squaredNorm() > 0 ? Eigen::Matrix3d(u * u.transpose() / u.squaredNorm())
                                                      : Eigen::Matrix3d::Identity();
    this->K += k * (across ? Eigen::Matrix3d(Eigen::Matrix3d::Identity() - along) : along);
  }
  double Largest() const noexcept {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
    solver.computeDirect(this->K, Eigen::EigenvaluesOnly);
    return std::max(0.0, solver.eigenvalues()(2));
  }
};
}  // namespace

void FixtureRenderer::SetDevice(const DeviceInfo& device) {
  this->Limits = DeviceInfo{};
  this->Limits.WorkspaceMin = device.WorkspaceMin;
  this->Limits.WorkspaceMax = device.WorkspaceMax;
  this->Limits.MaxForce = device.MaxForce;
  this->Limits.NominalMaxStiffness = device.NominalMaxStiffness;
  this->Limits.NominalMaxDamping = device.NominalMaxDamping;
  this->Limits.PhysicalDamping = device.PhysicalDamping;
  this->Limits.MaxForceRate = device.MaxForceRate;
  this->Limits.MaxTorque = device.MaxTorque;
}

void FixtureRenderer::Reset(const Vec3& tip) noexcept {
  for (int i = 0; i < MaxFixtures; ++i) {
    const uint32_t id = this->Memory[i].Id;
    this->Memory[i] = FixtureMemory{};
    this->Memory[i].Id = id;
  }
  this->Goal = tip;
  this->Residual = Vec3{};
  this->Initialized = true;
}

// A new snapshot: each fixture keeps its memory by id; one that left, or whose geometry or tuning
// changed, hands its force to the residual (which fades out) and, if still there, fades in anew.
void FixtureRenderer::Adopt(const FixtureSet* set) noexcept {
  FixtureMemory next[MaxFixtures];
  const VirtualFixture* geometry[MaxFixtures] = {};
  FixtureTuning tunings[MaxFixtures];
  bool kept[MaxFixtures] = {};
  const int count = set ? std::min(set->Count(), MaxFixtures) : 0;
  for (int j = 0; j < count; ++j) {
    const FixtureEntry& e = set->Entries[size_t(j)];
    geometry[j] = e.Fixture.get();
    tunings[j] = e.Tuning;
    next[j].Id = e.Fixture->Id();
    for (int i = 0; i < this->CurrentCount; ++i) {
      if (kept[i] || this->Memory[i].Id != next[j].Id) continue;
      kept[i] = true;
      if (this->Geometry[i] == geometry[j] && SameTuning(this->Tunings[i], tunings[j])) {
        next[j] = this->Memory[i];
      } else {
        this->Residual += this->Memory[i].Delivered;
      }
      break;
    }
  }
  for (int i = 0; i < this->CurrentCount; ++i)
    if (!kept[i]) this->Residual += this->Memory[i].Delivered;
  for (int j = 0; j < MaxFixtures; ++j) {
    this->Memory[j] = next[j];
    this->Geometry[j] = geometry[j];
    this->Tunings[j] = tunings[j];
  }
  this->Current = set;
  this->CurrentCount = count;
}

// A fixture switched off hands its force to the residual (which fades out); a wall arms once the
// goal is on its allowed side (one switched on behind the tool waits for it).
void FixtureRenderer::Arm(const FixtureSet& set, const FixtureTool& tool) noexcept {
  for (int i = 0; i < this->CurrentCount; ++i) {
    const FixtureEntry& e = set.Entries[size_t(i)];
    FixtureMemory& m = this->Memory[i];
    if (!e.Enabled) {
      if (m.Weight > 0) this->Residual += m.Delivered;
      m.Weight = 0;
      m.Delivered = Vec3{};
      m.Armed = m.Contact = m.Engaged = false;
      continue;
    }
    if (e.Fixture->IsWall() && !m.Armed && e.Fixture->Allowed(e.Tuning, this->Goal, tool.Radius, m)) m.Armed = true;
  }
}

// The walls in turn until none moves the goal. A wall touched in any round is in contact this
// tick (a later round sees the goal already on it); each round starts from what it knew last tick.
Vec3 FixtureRenderer::ConstrainWalls(const FixtureSet& set, const FixtureTool& tool) noexcept {
  const Vec3 from = tool.HasFrom ? tool.From : this->Goal;
  Vec3 goal = tool.Tip;
  bool before[MaxFixtures], touched[MaxFixtures];
  Vec3 normal[MaxFixtures];
  for (int i = 0; i < this->CurrentCount; ++i) {
    before[i] = this->Memory[i].Contact;
    touched[i] = false;
  }
  // Each wall in turn; a wall that moved the goal is not asked again until another one moved it
  // (a wall's own answer stands: sliding is not idempotent to the last micrometre).
  int mover = -1, quiet = 0, armed = 0;
  for (int i = 0; i < this->CurrentCount; ++i) armed += this->Memory[i].Armed && set.Entries[size_t(i)].Enabled;
  bool agreed = armed <= 1;
  for (int visit = 0; visit < ConstrainRounds * this->CurrentCount && quiet < armed; ++visit) {
    const int i = visit % this->CurrentCount;
    const FixtureEntry& e = set.Entries[size_t(i)];
    FixtureMemory& m = this->Memory[i];
    if (!m.Armed || !e.Enabled) continue;
    if (i == mover) {
      ++quiet;
      continue;
    }
    m.Contact = before[i];
    const Vec3 next = e.Fixture->Constrain(e.Tuning, from, goal, tool.Radius, m);
    if (m.Contact) {
      touched[i] = true;
      normal[i] = m.ContactNormal;
    }
    if (Norm2(next - goal) > 1e-12) {  // moved by more than a micrometre
      goal = next;
      mover = i;
      quiet = 0;
    } else {
      ++quiet;
    }
  }
  agreed = agreed || quiet >= armed;
  for (int i = 0; i < this->CurrentCount; ++i) {
    FixtureMemory& m = this->Memory[i];
    m.Contact = touched[i];
    if (touched[i]) m.ContactNormal = normal[i];
  }
  return agreed ? goal : from;  // the walls did not agree on a point (a corner): the tool stays
}

// Each fixture's weight moves towards 1 (on and engaged) or 0 by at most its share of the event
// budget over its force; the residual of fixtures gone fades first, from half the budget.
void FixtureRenderer::Fade(const FixtureSet& set, const FixtureForce* forces, double stiffnessScale, double dampingScale,
                           double budget) noexcept {
  const double residual = Norm(this->Residual);
  int changing = 0;
  double target[MaxFixtures];
  for (int i = 0; i < this->CurrentCount; ++i) {
    const FixtureEntry& e = set.Entries[size_t(i)];
    const bool on = e.Enabled && (e.Fixture->IsWall() ? this->Memory[i].Armed : forces[i].Engaged);
    target[i] = on ? 1.0 : 0.0;
    changing += this->Memory[i].Weight != target[i];
  }
  const double forResidual = std::min(residual, changing > 0 ? 0.5 * budget : budget);
  if (residual > 0) this->Residual = this->Residual * ((residual - forResidual) / residual);
  const double share = changing > 0 ? (budget - forResidual) / changing : 0;
  for (int i = 0; i < this->CurrentCount; ++i) {
    FixtureMemory& m = this->Memory[i];
    if (m.Weight == target[i]) continue;
    const double magnitude = Norm(forces[i].Spring * stiffnessScale + forces[i].Damper * dampingScale);
    const double step = magnitude > 1e-12 ? share / magnitude : 1.0;
    m.Weight = m.Weight < target[i] ? std::min(target[i], m.Weight + step) : std::max(target[i], m.Weight - step);
  }
}

const FixtureOutput& FixtureRenderer::Update(const FixtureSet* set, const FixtureTool& tool, double dt, double period,
                                             double workspaceScale) noexcept {
  double k, b;
  this->Constrain(set, tool, period, workspaceScale, k, b);
  return this->Render(set, tool, dt, period, workspaceScale);
}

const Vec3& FixtureRenderer::Constrain(const FixtureSet* set, const FixtureTool& tool, double period, double workspaceScale,
                                       double& stiffness, double& damping) noexcept {
  if (!this->Initialized) this->Reset(tool.Tip);
  if (set != this->Current) this->Adopt(set);
  this->Constrained = true;
  stiffness = damping = 0;
  if (set == nullptr || this->CurrentCount == 0) {
    this->Goal = tool.Tip;
    return this->Goal;
  }
  this->Arm(*set, tool);
  this->Goal = this->ConstrainWalls(*set, tool);
  // The gains that will act: walls pressed now, guides holding the tool (or fading).
  StiffnessMatrix matrix;
  double b = 0;
  for (int i = 0; i < this->CurrentCount; ++i) {
    const FixtureEntry& e = set->Entries[size_t(i)];
    const FixtureMemory& m = this->Memory[i];
    const bool wall = e.Fixture->IsWall();
    if (!e.Enabled || !(wall ? m.Contact : (m.Engaged || m.Weight > 0))) continue;
    matrix.Add(e.Tuning.Stiffness, wall ? m.ContactNormal : m.SpringDirection, !wall && m.SpringAcross);
    b += e.Tuning.Damping;
  }
  const double k = matrix.Largest();
  if (k > 0) {
    const GainLimits g = LimitGains(k, b, this->Limits, period > 0 ? period : 0.001, workspaceScale);
    stiffness = g.Stiffness;
    damping = g.Damping;
  }
  return this->Goal;
}

GainLimits FixtureRenderer::Gains(const FixtureSet& set, const FixtureForce* forces, double period,
                                  double workspaceScale) const noexcept {
  StiffnessMatrix matrix;
  double b = 0;
  for (int i = 0; i < this->CurrentCount; ++i)
    if (forces[i].Stiffness > 0) {
      matrix.Add(forces[i].Stiffness, forces[i].Direction, forces[i].Across);
      b += set.Entries[size_t(i)].Tuning.Damping;
    }
  const double k = matrix.Largest();
  return k > 0 ? LimitGains(k, b, this->Limits, period, workspaceScale) : GainLimits{};
}

const FixtureOutput& FixtureRenderer::Render(const FixtureSet* set, const FixtureTool& tool, double dt, double period,
                                             double workspaceScale) noexcept {
  if (!this->Constrained) {
    double k, b;
    this->Constrain(set, tool, period, workspaceScale, k, b);
  }
  this->Constrained = false;
  FixtureOutput& out = this->Out;
  out.Count = this->CurrentCount;
  const double tick = period > 0 ? period : 0.001;
  out.Goal = this->Goal;
  out.Blocked = Norm2(this->Goal - tool.Tip) > 1e-24;

  // Each fixture's force, the gains they render together, and the fades.
  FixtureForce forces[MaxFixtures];
  for (int i = 0; i < this->CurrentCount; ++i) {
    const FixtureEntry& e = set->Entries[size_t(i)];
    FixtureMemory& m = this->Memory[i];
    if (!e.Enabled) {
      m.HasLast = false;
      continue;
    }
    e.Fixture->Evaluate(e.Tuning, tool, this->Goal, dt > 0 ? dt : tick, m, forces[i]);
    if (forces[i].Stiffness > 0) {
      m.SpringDirection = forces[i].Direction;
      m.SpringAcross = forces[i].Across;
    }
  }
  const GainLimits gains = set ? this->Gains(*set, forces, tick, workspaceScale) : GainLimits{};
  if (set) this->Fade(*set, forces, gains.StiffnessScale, gains.DampingScale, this->Limits.MaxForceRate * tick);

  out.Force = this->Residual;
  out.Torque = Vec3{};
  out.Stiffness = gains.Stiffness;  // the springs together, as the device feels them
  out.Damping = out.Stored = 0;
  out.Active = Norm2(this->Residual) > 0;
  for (int i = 0; i < this->CurrentCount; ++i) {
    const FixtureEntry& e = set->Entries[size_t(i)];
    FixtureMemory& m = this->Memory[i];
    const FixtureForce& f = forces[i];
    m.Delivered = (f.Spring * gains.StiffnessScale + f.Damper * gains.DampingScale) * m.Weight;
    out.Force += m.Delivered;
    out.Torque += f.Torque * m.Weight;
    out.Damping += f.Stiffness > 0 ? e.Tuning.Damping * gains.DampingScale * m.Weight : 0.0;
    out.Stored += f.Stored * gains.StiffnessScale * m.Weight;
    out.Active = out.Active || (m.Weight > 0 && (f.Stiffness > 0 || Norm2(f.Damper) > 0));
    FixtureReport& r = out.Fixtures[i];
    r.Id = m.Id;
    r.Kind = e.Fixture->Kind();
    r.Enabled = e.Enabled;
    r.Engaged = f.Engaged;
    r.Armed = m.Armed;
    r.Contact = m.Contact;
    r.Weight = m.Weight;
    r.Distance = m.Distance;
    r.Force = m.Delivered;
  }
  return out;
}

}  // namespace rp
