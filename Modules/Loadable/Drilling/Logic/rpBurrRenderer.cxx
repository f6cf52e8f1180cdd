#include "rpBurrRenderer.h"

#include <algorithm>
#include <cmath>

namespace rp {

BurrRenderer::BurrRenderer() { this->SetDevice(DeviceInfo{}); }

void BurrRenderer::SetDevice(const DeviceInfo& device) {
  this->DeviceLimits = device;
  this->Observer.SetMaxDamping(device.NominalMaxDamping);
}

void BurrRenderer::Reset(const Vec3& hip) noexcept {
  this->God.Reset(hip);
  this->LastHip = this->LastHeld = hip;
  this->LastProxy = hip;
  this->Observer.Reset(hip);
  this->WasInContact = false;
  this->Initialized = true;
  this->Out = BurrForce{};
  this->Out.Hip = this->Out.Goal = this->Out.Proxy = this->Out.Anchor = hip;
}

const BurrForce& BurrRenderer::Update(const DrillVolume& volume, const Vec3& hip, double radius, double otherStiffness,
                                      double otherDamping, double elapsed, ToolConstraints* constraints,
                                      const Pose& stylus) noexcept {
  if (!this->Initialized) this->Reset(hip);
  BurrForce& out = this->Out;
  const double period = this->Options.Period > 0 ? this->Options.Period : 0.001;
  const double dt = elapsed > 0 ? elapsed : period;
  const Vec3 hipVelocity = (hip - this->LastHip) / dt;

  // Step 0: where the constraints' walls let the burr's centre go; the burr meets the bone there.
  ConstraintContext tool;
  tool.Dt = dt;
  tool.Period = period;
  tool.Stylus = stylus;
  tool.Tip = hip;
  tool.TipVelocity = hipVelocity;
  tool.Radius = radius;
  tool.Device = &this->DeviceLimits;
  tool.WorkspaceScale = this->Options.WorkspaceScale;
  tool.From = this->God.Position();  // the burr lags the hand where it cuts: the walls start from it
  tool.HasFrom = true;
  ConstraintGoal goal;
  goal.Goal = hip;
  if (constraints != nullptr) goal = constraints->Constrain(tool);
  const Vec3& held = goal.Goal;
  out.Goal = held;
  out.Contact = this->God.Update(volume, held, radius);
  const BurrContact& c = out.Contact;
  out.Hip = hip;
  out.Proxy = this->God.Position();
  out.Anchor = c.Anchor;
  const Vec3 heldVelocity = (held - this->LastHeld) / dt;
  const Vec3 proxyVelocity = (out.Proxy - this->LastProxy) / dt;
  this->LastHip = hip;
  this->LastHeld = held;
  this->LastProxy = out.Proxy;

  Vec3 total{};
  out.Gains = GainLimits{};
  out.Depth = 0;
  out.Stiffness = 0;
  const bool touching = c.InContact && c.Material > 0 && size_t(c.Material) <= volume.Materials().size();
  if (touching) {
    const Material& m = volume.Materials()[c.Material - 1];
    double k = m.Stiffness, b = m.Damping;
    if (this->Options.LimitGains) {
      // Share the device's passive budget with the other contacts rendered this tick.
      const DeviceInfo budget =
          RemainingBudget(this->DeviceLimits, otherStiffness + goal.Stiffness, otherDamping + goal.Damping, period);
      out.Gains = LimitGains(k, b, budget, period, this->Options.WorkspaceScale);
      k *= out.Gains.StiffnessScale;
      b *= out.Gains.DampingScale;
    }
    out.Stiffness = k;
    const Vec3 stretch = out.Anchor - held;  // eq. 1: Δd = x_proxy − x_probe (the burr as the walls hold it)
    out.Depth = Norm2(c.Normal) > 0 ? std::max(0.0, Dot(stretch, c.Normal)) : Norm(stretch);
    total = stretch * k + (proxyVelocity - heldVelocity) * b;
  }

  // Virtual fixtures on the burr's centre, beside the bone's contact (rpToolConstraint.h).
  out.Constraint = ConstraintForce{};
  if (constraints != nullptr) {
    tool.Proxy = out.Proxy;
    tool.InContact = touching;
    tool.ContactStiffness = otherStiffness + (touching ? out.Gains.Stiffness : 0.0);
    tool.ContactDamping = otherDamping + (touching ? out.Gains.Damping : 0.0);
    out.Constraint = constraints->Evaluate(tool);
    total += out.Constraint.Force;
  }
  const bool engaged = touching || out.Constraint.Engaged;

  // Passivity over each contact (or fixture) episode, following the HIP (where the device applies the force).
  if (engaged && !this->WasInContact) this->Observer.Reset(hip - hipVelocity * dt);
  if (engaged || this->WasInContact) this->Observer.Observe(hip);
  if (engaged && this->Options.PassivityControl)
    total = this->Observer.Correct(hipVelocity, total, dt, out.Constraint.StoredEnergy);
  out.ObservedEnergy = this->Observer.ObservedEnergy();
  out.AddedDamping = engaged && this->Options.PassivityControl ? this->Observer.AddedDamping() : 0.0;
  this->WasInContact = engaged;

  // eq. 6: clamp the magnitude, keep the direction.
  out.UnclampedForce = total;
  const double magnitude = Norm(total);
  out.Clamped = magnitude > this->DeviceLimits.MaxForce;
  out.Force = out.Clamped ? total * (this->DeviceLimits.MaxForce / magnitude) : total;
  this->Observer.Held(out.Force);
  return out;
}

}  // namespace rp
