#pragma once
// The virtual fixtures of a plan (a FixtureSet) plugged into a servo as one ToolConstraint
// (rpToolConstraint.h): before the tissue contact their walls move the tool point (Constrain),
// after it their springs add their force (Evaluate), with the fades and gain limits of
// rpFixtureRenderer. A new set published while the servo runs (a fixture switched, the plan
// dragged) carries the servo-side state over (CarryFrom): each fixture keeps its fade and proxy
// by id, and what changed fades instead of jumping. Never allocates, locks or logs on the servo.
#include <functional>
#include <memory>

#include "rpFixtureRenderer.h"
#include "rpToolConstraint.h"

namespace rp {

class FixtureConstraint : public ToolConstraint {
 public:
  explicit FixtureConstraint(std::shared_ptr<const FixtureSet> set) : Set(std::move(set)) {}
  void Constrain(const ConstraintContext& tool, ConstraintGoal& goal) noexcept override;
  void Evaluate(const ConstraintContext& tool, ConstraintForce& out) noexcept override;
  void CarryFrom(const ToolConstraint& previous) noexcept override;
  /// The fixtures after the last tick (servo thread, or any thread once the servo stopped).
  const FixtureOutput& Output() const { return this->Renderer.Output(); }
  const FixtureSet& Fixtures() const { return *this->Set; }

 private:
  FixtureTool Tool(const ConstraintContext& context, const Vec3& tip) const noexcept;
  std::shared_ptr<const FixtureSet> Set;
  FixtureRenderer Renderer;
  bool HasDevice = false;
};

/// A constraint set holding the fixtures: what a logic's SetConstraints maker returns.
std::unique_ptr<ToolConstraints> MakeFixtureConstraints(std::shared_ptr<const FixtureSet> set);

/// What a logic's SetPlanFixtures does with a built set: `make` hands it to every next session,
/// and `running` (the running servo's exchange; null when none runs) gets it now. Even an empty
/// set goes in as a fixture constraint: it carries the fades of the fixtures switched off.
void InstallFixtures(std::shared_ptr<const FixtureSet> set, std::function<std::unique_ptr<ToolConstraints>()>& make,
                     ConstraintExchange* running);

}  // namespace rp
