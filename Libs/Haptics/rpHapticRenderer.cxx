#include "rpHapticRenderer.h"

#include <cmath>

namespace rp {

HapticRenderer::HapticRenderer() { this->SetDevice(DeviceInfo{}); }

bool HapticRenderer::SetToolPoints(const Vec3* points, int count) {
  if (count < 1 || count > MaxToolPoints) return false;
  for (int i = 0; i < count; ++i) this->ToolPoints[i] = points[i];
  this->PointCount = count;
  this->Initialized = false;
  return true;
}

void HapticRenderer::SetDevice(const DeviceInfo& device) {
  this->Device = device;
  this->MaxForce = device.MaxForce;
  this->Observer.SetMaxDamping(device.NominalMaxDamping);
}

void HapticRenderer::Reset(const Pose& pose) noexcept {
  for (int i = 0; i < this->PointCount; ++i) {
    const Vec3 hip = pose.Apply(this->ToolPoints[i]);
    this->Proxies[i].Reset(hip);
    this->LastHip[i] = hip;
    this->LastProxy[i] = hip;
  }
  this->LastTip = this->LastHip[0];
  this->Observer.Reset(this->LastTip);
  this->WasInContact = false;
  this->Initialized = true;
  this->Out = RenderOutput{};
  this->Out.NumberOfPoints = this->PointCount;
}

const RenderOutput& HapticRenderer::Update(const Pose& device, double elapsed, ToolConstraints* constraints) noexcept {
  if (!this->Initialized) this->Reset(device);
  RenderOutput& out = this->Out;
  out.NumberOfPoints = this->PointCount;
  out.Contacts = 0;
  out.PrimaryPoint = -1;
  const double period = this->Options.Period > 0 ? this->Options.Period : 0.001;
  const double dt = elapsed > 0 ? elapsed : period;
  const bool stalled = dt > 1.5 * period;
  const Vec3 previousForce = out.Force;

  // Step 0: the constraints' walls decide where the tool may be; the tissue touches it there.
  ConstraintContext tool = this->ToolContext(device, dt, period);
  out.Tip = tool.Tip;
  ConstraintGoal goal;
  goal.Goal = tool.Tip;
  if (constraints != nullptr) goal = constraints->Constrain(tool);
  out.Goal = goal.Goal;
  Pose pose = device;
  pose.T += goal.Goal - tool.Tip;

  // Pass 1: proxies, and the summed gains of the points in contact (eq. 4–5 act in parallel).
  double kSum = 0, bSum = 0, deepest = -1;
  for (int i = 0; i < this->PointCount; ++i) {
    PointContact& c = out.Points[i];
    c.Hip = pose.Apply(this->ToolPoints[i]);
    c.Force = Vec3{};
    if (this->Scene == nullptr || this->Scene->Tree.Empty()) {
      this->Proxies[i].Reset(c.Hip);
      c.Proxy = c.Hip;
      c.InContact = false;
      c.Planes = 0;
      c.Depth = 0;
      continue;
    }
    const ProxyState& s = this->Proxies[i].Update(*this->Scene, c.Hip, this->Options.Friction, this->Options.ForceShading);
    c.Proxy = s.Proxy;
    c.InContact = s.InContact;
    c.Planes = s.PlaneCount;
    c.Label = s.Label;
    c.Depth = s.InContact ? std::fabs(Dot(s.Proxy - c.Hip, s.ForceNormal)) : 0.0;
    if (s.InContact) {
      const Material& m = this->Scene->Materials[s.Label];
      kSum += m.Stiffness;
      bSum += m.Damping;
      ++out.Contacts;
      if (c.Depth > deepest) {
        deepest = c.Depth;
        out.PrimaryPoint = i;
      }
    }
  }
  out.Gains = GainLimits{};
  if (this->Options.LimitGains && out.Contacts > 0)  // within what the constraints left of the budget
    out.Gains = LimitGains(kSum, bSum, RemainingBudget(this->Device, goal.Stiffness, goal.Damping, period), period,
                           this->Options.WorkspaceScale);

  // Pass 2: spring-damper per contact with the limited gains, summed (eq. 4).
  Vec3 total{};
  double renderedStiffness = 0, largestMove = 0, stored = 0;
  for (int i = 0; i < this->PointCount; ++i) {
    PointContact& c = out.Points[i];
    largestMove = std::fmax(largestMove, Norm(c.Hip - this->LastHip[i]));
    const Vec3 hipVelocity = (c.Hip - this->LastHip[i]) / dt;
    const Vec3 proxyVelocity = (c.Proxy - this->LastProxy[i]) / dt;
    this->LastHip[i] = c.Hip;
    this->LastProxy[i] = c.Proxy;
    if (!c.InContact) continue;
    const ProxyState& s = this->Proxies[i].State();
    const Material& m = this->Scene->Materials[c.Label];
    const double k = m.Stiffness * out.Gains.StiffnessScale;
    const double b = m.Damping * out.Gains.DampingScale;
    renderedStiffness += k;
    stored += 0.5 * k * Norm2(c.Proxy - c.Hip);  // what this spring will give back
    const Vec3 stretch = c.Proxy - c.Hip;  // eq. 1: Δd = x_proxy − x_probe
    // Force shading: the normal part of the spring turns to the shaded normal.
    const Vec3 faceNormal = s.PlaneCount == 1 ? s.Planes[0].Normal : s.ForceNormal;
    const double normalPart = Dot(stretch, faceNormal);
    const Vec3 shadedStretch = stretch - faceNormal * normalPart + s.ForceNormal * normalPart;
    c.Force = shadedStretch * k + (proxyVelocity - hipVelocity) * b;
    total += c.Force;
  }

  // Virtual fixtures on the device's tip, beside the contacts (rpToolConstraint.h).
  const Vec3 tip = out.Tip;
  out.Constraint = ConstraintForce{};
  if (constraints != nullptr) {
    out.Constraint = this->EvaluateConstraints(*constraints, tool);
    total += out.Constraint.Force;
    stored += out.Constraint.StoredEnergy;
    renderedStiffness += out.Constraint.Stiffness;
  }

  // Passivity: each contact (or fixture) episode must not create energy. The observer follows the
  // tip (where the device applies the force) and accounts the exit step too.
  const bool touching = out.Contacts > 0 || out.Constraint.Engaged;
  if (touching && !this->WasInContact) this->Observer.Reset(this->LastTip);
  if (touching || this->WasInContact) this->Observer.Observe(tip);
  if (touching && this->Options.PassivityControl) total = this->Observer.Correct((tip - this->LastTip) / dt, total, dt, stored);
  out.ObservedEnergy = this->Observer.ObservedEnergy();
  out.AddedDamping = touching && this->Options.PassivityControl ? this->Observer.AddedDamping() : 0.0;
  this->WasInContact = touching;
  this->LastTip = tip;

  // After a stall: no more force than before plus what the motion justifies (k·|Δx|).
  out.StallLimited = false;
  if (stalled) {
    const double bound = Norm(previousForce) + renderedStiffness * largestMove;
    const double magnitude = Norm(total);
    if (magnitude > bound) {
      total = magnitude > 0 ? total * (bound / magnitude) : total;
      out.StallLimited = true;
    }
  }

  // eq. 6: clamp the magnitude, keep the direction.
  out.UnclampedForce = total;
  const double magnitude = Norm(total);
  out.Clamped = magnitude > this->MaxForce;
  out.Force = out.Clamped ? total * (this->MaxForce / magnitude) : total;
  this->Observer.Held(out.Force);
  return out;
}

ConstraintContext HapticRenderer::ToolContext(const Pose& device, double dt, double period) const noexcept {
  ConstraintContext tool;
  tool.Dt = dt;
  tool.Period = period;
  tool.Stylus = device;
  tool.Tip = device.Apply(this->ToolPoints[0]);
  tool.TipVelocity = (tool.Tip - this->LastTip) / dt;
  tool.Device = &this->Device;
  tool.WorkspaceScale = this->Options.WorkspaceScale;
  return tool;
}

ConstraintForce HapticRenderer::EvaluateConstraints(ToolConstraints& constraints, ConstraintContext& tool) noexcept {
  const RenderOutput& out = this->Out;
  tool.Proxy = out.Points[0].Proxy;
  tool.InContact = out.Contacts > 0;
  tool.ContactStiffness = out.Contacts > 0 ? out.Gains.Stiffness : 0.0;
  tool.ContactDamping = out.Contacts > 0 ? out.Gains.Damping : 0.0;
  return constraints.Evaluate(tool);
}

}  // namespace rp
