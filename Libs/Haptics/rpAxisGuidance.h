#pragma once
// Axis guidance: within the capture radius of a planned trajectory's axis (and not beyond its
// target by more than the capture radius) a spring pulls the tool onto the axis, normal to it, and
// leaves it free along it: F = −k·(the tool's offset from the axis) − b·(its velocity across the
// axis). Beyond the release radius it lets go (hysteresis). On a device with torque output the
// tool's direction is pulled to the axis's too: τ = k_θ·θ about (tool direction × axis).
#include <memory>

#include "rpTrajectoryAxis.h"
#include "rpVirtualFixture.h"

namespace rp {

class AxisGuidance : public VirtualFixture {
 public:
  AxisGuidance(uint32_t id, std::string name, const TrajectoryAxis& axis)
      : VirtualFixture(FixtureKind::AxisGuidance, id, std::move(name)), Axis(axis) {}
  const TrajectoryAxis& Trajectory() const { return this->Axis; }
  void Evaluate(const FixtureTuning& tuning, const FixtureTool& tool, const Vec3& goal, double dt, FixtureMemory& memory,
                FixtureForce& out) const noexcept override;

 private:
  TrajectoryAxis Axis;
};

}  // namespace rp
