#pragma once
// Depth stop: a one-sided wall across a planned trajectory at its target depth. Within the capture
// radius of the axis the tool point (a stylus tip, a burr centre) cannot go deeper than the target:
// every move is tested as a segment against the wall's plane (swept, so no speed pops it through),
// the proxy slides on the wall, and the hand feels a spring-damper past it. A tool already beyond
// the wall (switched on late, or come round its edge) is not pushed back: the wall holds once the
// tool is in front of it again.
#include "rpTrajectoryAxis.h"
#include "rpVirtualFixture.h"

namespace rp {

class DepthStop : public VirtualFixture {
 public:
  DepthStop(uint32_t id, std::string name, const TrajectoryAxis& axis)
      : VirtualFixture(FixtureKind::DepthStop, id, std::move(name)), Axis(axis) {}
  const TrajectoryAxis& Trajectory() const { return this->Axis; }
  Vec3 Constrain(const FixtureTuning& tuning, const Vec3& from, const Vec3& to, double radius,
                 FixtureMemory& memory) const noexcept override;
  bool Allowed(const FixtureTuning& tuning, const Vec3& p, double radius, FixtureMemory& memory) const noexcept override;
  void Evaluate(const FixtureTuning& tuning, const FixtureTool& tool, const Vec3& goal, double dt, FixtureMemory& memory,
                FixtureForce& out) const noexcept override;

 private:
  TrajectoryAxis Axis;
};

}  // namespace rp
