#include "rpFixtureSet.h"

#include <cmath>

#include "rpStability.h"

namespace rp {

std::string FixtureTuningProblem(const FixtureTuning& t) {
  if (!(t.Stiffness >= 0) || !std::isfinite(t.Stiffness)) return "stiffness must be a number ≥ 0 N/mm";
  if (!(t.Damping >= 0) || !std::isfinite(t.Damping)) return "damping must be a number ≥ 0 N·s/mm";
  if (!(t.Capture >= 0) || !std::isfinite(t.Capture)) return "capture distance must be a number ≥ 0 mm";
  if (!(t.Release >= t.Capture) || !std::isfinite(t.Release)) return "release distance must be at least the capture distance";
  if (!(t.AngularStiffness >= 0) || !std::isfinite(t.AngularStiffness)) return "angular stiffness must be ≥ 0 N·mm/rad";
  return "";
}

bool FixtureSet::Add(std::shared_ptr<const VirtualFixture> fixture, const FixtureTuning& tuning, bool enabled,
                     std::string& error) {
  if (!fixture) {
    error = "fixture set: no fixture";
    return false;
  }
  const std::string what = std::string(FixtureKindName(fixture->Kind())) + " fixture '" + fixture->Name() + "'";
  if (this->Count() >= MaxFixtures) {
    error = what + ": at most " + std::to_string(MaxFixtures) + " fixtures at once";
    return false;
  }
  if (this->Find(fixture->Id())) {
    error = what + ": id " + std::to_string(fixture->Id()) + " is already used";
    return false;
  }
  const std::string problem = FixtureTuningProblem(tuning);
  if (!problem.empty()) {
    error = what + ": " + problem;
    return false;
  }
  this->Entries.push_back({std::move(fixture), tuning, enabled});
  return true;
}

const FixtureEntry* FixtureSet::Find(uint32_t id) const {
  for (const FixtureEntry& e : this->Entries)
    if (e.Fixture->Id() == id) return &e;
  return nullptr;
}

std::unique_ptr<FixtureSet> FixtureSet::WithKindEnabled(FixtureKind kind, bool enabled) const {
  auto copy = std::make_unique<FixtureSet>(*this);
  for (FixtureEntry& e : copy->Entries)
    if (e.Fixture->Kind() == kind) e.Enabled = enabled;
  copy->Version = this->Version + 1;
  return copy;
}

FixtureTuning DefaultFixtureTuning(FixtureKind kind) {
  FixtureTuning t;
  switch (kind) {
    case FixtureKind::AxisGuidance:  // holds the tool on the axis against a light lateral grip
      t.Stiffness = 0.6, t.Damping = 0.0005, t.Capture = 3, t.Release = 4.5;
      break;
    case FixtureKind::DepthStop:  // holds across a tunnel's width and the hand's wander
      t.Stiffness = 0.6, t.Damping = 0.001, t.Capture = 5, t.Release = 5;
      break;
    case FixtureKind::ForbiddenRegion:  // the approach damped over the last 2 mm
      t.Stiffness = 0.6, t.Damping = 0.001, t.Capture = 2, t.Release = 2;
      break;
    case FixtureKind::SurfaceConstraint:
      t.Stiffness = 0.4, t.Damping = 0.0005, t.Capture = 2, t.Release = 3;
      break;
  }
  return t;
}

double RenderedFixtureStiffness(const FixtureTuning& t, const DeviceInfo& device, double period, double workspaceScale) {
  return t.Stiffness * LimitGains(t.Stiffness, t.Damping, device, period, workspaceScale).StiffnessScale;
}

}  // namespace rp
