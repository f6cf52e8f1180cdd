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
  this->LastHip = hip;
  this->LastProxy = hip;
  this->Observer.Reset(hip);
  this->WasInContact = false;
  this->Initialized = true;
  this->Out = BurrForce{};
  this->Out.Hip = this->Out.Proxy = this->Out.Anchor = hip;
}

const BurrForce& BurrRenderer::Update(const DrillVolume& volume, const Vec3& hip, double radius, double otherStiffness,
                                      double otherDamping, double elapsed) noexcept {
  if (!this->Initialized) this->Reset(hip);
  BurrForce& out = this->Out;
  const double period = this->Options.Period > 0 ? this->Options.Period : 0.001;
  const double dt = elapsed > 0 ? elapsed : period;
  out.Contact = this->God.Update(volume, hip, radius);
  const BurrContact& c = out.Contact;
  out.Hip = hip;
  out.Proxy = this->God.Position();
  out.Anchor = c.Anchor;
  const Vec3 hipVelocity = (hip - this->LastHip) / dt;
  const Vec3 proxyVelocity = (out.Proxy - this->LastProxy) / dt;
  this->LastHip = hip;
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
      const DeviceInfo budget = RemainingBudget(this->DeviceLimits, otherStiffness, otherDamping, period);
      out.Gains = LimitGains(k, b, budget, period, this->Options.WorkspaceScale);
      k *= out.Gains.StiffnessScale;
      b *= out.Gains.DampingScale;
    }
    out.Stiffness = k;
    const Vec3 stretch = out.Anchor - hip;  // eq. 1: Δd = x_proxy − x_probe
    out.Depth = Norm2(c.Normal) > 0 ? std::max(0.0, Dot(stretch, c.Normal)) : Norm(stretch);
    total = stretch * k + (proxyVelocity - hipVelocity) * b;
  }

  // Passivity over each contact episode, following the HIP (where the device applies the force).
  if (touching && !this->WasInContact) this->Observer.Reset(hip - hipVelocity * dt);
  if (touching || this->WasInContact) this->Observer.Observe(hip);
  if (touching && this->Options.PassivityControl) total = this->Observer.Correct(hipVelocity, total, dt);
  out.ObservedEnergy = this->Observer.ObservedEnergy();
  out.AddedDamping = touching && this->Options.PassivityControl ? this->Observer.AddedDamping() : 0.0;
  this->WasInContact = touching;

  // eq. 6: clamp the magnitude, keep the direction.
  out.UnclampedForce = total;
  const double magnitude = Norm(total);
  out.Clamped = magnitude > this->DeviceLimits.MaxForce;
  out.Force = out.Clamped ? total * (this->DeviceLimits.MaxForce / magnitude) : total;
  this->Observer.Held(out.Force);
  return out;
}

}  // namespace rp
