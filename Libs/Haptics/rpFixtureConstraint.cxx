#include "rpFixtureConstraint.h"

#include "rpHapticRenderer.h"

namespace rp {

FixtureTool FixtureConstraint::Tool(const ConstraintContext& context, const Vec3& tip) const noexcept {
  return FixtureTool{tip, Normalized(context.Stylus.Rotate(ToolForward)), context.Radius, context.From, context.HasFrom};
}

void FixtureConstraint::Constrain(const ConstraintContext& tool, ConstraintGoal& goal) noexcept {
  if (!this->HasDevice && tool.Device) {
    this->Renderer.SetDevice(*tool.Device);  // numbers only: no allocation
    this->HasDevice = true;
  }
  double k = 0, b = 0;
  goal.Goal = this->Renderer.Constrain(this->Set.get(), this->Tool(tool, goal.Goal), tool.Period, tool.WorkspaceScale, k, b);
  goal.Stiffness += k;
  goal.Damping += b;
}

void FixtureConstraint::Evaluate(const ConstraintContext& tool, ConstraintForce& out) noexcept {
  const FixtureOutput& f = this->Renderer.Render(this->Set.get(), this->Tool(tool, tool.Tip), tool.Dt, tool.Period,
                                                 tool.WorkspaceScale);
  out.Force += f.Force;
  out.Torque += f.Torque;
  out.Stiffness += f.Stiffness;
  out.Damping += f.Damping;
  out.StoredEnergy += f.Stored;
  out.Engaged = out.Engaged || f.Active;
  out.Fixtures = &f;
}

void FixtureConstraint::CarryFrom(const ToolConstraint& previous) noexcept {
  const auto& before = static_cast<const FixtureConstraint&>(previous);  // same class: ToolConstraints::CarryFrom checks
  this->Renderer = before.Renderer;  // fades, proxies, contacts; a changed set is adopted by id on the next tick
  this->HasDevice = before.HasDevice;
}

std::unique_ptr<ToolConstraints> MakeFixtureConstraints(std::shared_ptr<const FixtureSet> set) {
  auto constraints = std::make_unique<ToolConstraints>();
  constraints->Add(std::make_unique<FixtureConstraint>(std::move(set)));
  return constraints;
}

void InstallFixtures(std::shared_ptr<const FixtureSet> set, std::function<std::unique_ptr<ToolConstraints>()>& make,
                     ConstraintExchange* running) {
  if (running) running->Publish(MakeFixtureConstraints(set));
  make = [set] { return MakeFixtureConstraints(set); };
}

}  // namespace rp
