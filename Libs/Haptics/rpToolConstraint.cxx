#include "rpToolConstraint.h"

#include <typeinfo>

namespace rp {

ConstraintGoal ToolConstraints::Constrain(const ConstraintContext& tool) noexcept {
  ConstraintGoal goal;
  goal.Goal = tool.Tip;
  for (const auto& constraint : this->Items) constraint->Constrain(tool, goal);
  return goal;
}

ConstraintForce ToolConstraints::Evaluate(const ConstraintContext& tool) noexcept {
  ConstraintForce out;
  for (const auto& constraint : this->Items) constraint->Evaluate(tool, out);
  return out;
}

void ToolConstraints::CarryFrom(const ToolConstraints& previous) noexcept {
  for (size_t i = 0; i < this->Items.size() && i < previous.Items.size(); ++i)
    if (typeid(*this->Items[i]) == typeid(*previous.Items[i])) this->Items[i]->CarryFrom(*previous.Items[i]);
}

}  // namespace rp
