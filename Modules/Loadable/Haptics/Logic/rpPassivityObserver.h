#pragma once
// Passivity observer / controller (Hannaford & Ryu, IEEE TRO 2002). It integrates the energy the
// virtual environment absorbed from the user, using the force actually held by the device over
// each period (zero-order hold) and the displacement over that period:
//     E(n) = E(n−1) − F(n−1)·(x(n) − x(n−1)).
// A passive environment keeps E ≥ 0. When E turns negative the controller adds the damping
// α = −E / (|v|² T) (capped) that dissipates the excess, opposing the current velocity.
// Plain arithmetic, no allocation.
#include "rpVec3.h"

namespace rp {

class PassivityObserver {
 public:
  explicit PassivityObserver(double maxDamping = 0.002) : MaxDamping(maxDamping) {}
  void SetMaxDamping(double b) { this->MaxDamping = b; }
  /// Forget the energy (e.g. when contact ends: every contact episode must be passive).
  void Reset(const Vec3& position) noexcept {
    this->Energy = 0;
    this->LastPosition = position;
    this->LastForce = Vec3{};
    this->Alpha = 0;
  }
  /// Accounts the step to `position` with the force held since the previous step.
  void Observe(const Vec3& position) noexcept {
    this->Energy -= Dot(this->LastForce, position - this->LastPosition);
    this->LastPosition = position;
  }
  /// `force` plus the damping that dissipates a negative energy at `velocity` (capped).
  Vec3 Correct(const Vec3& velocity, const Vec3& force, double period) noexcept {
    this->Alpha = 0;
    const double v2 = Norm2(velocity);
    if (this->Energy >= 0 || v2 <= 1e-12 || period <= 0) return force;
    this->Alpha = -this->Energy / (v2 * period);
    if (this->Alpha > this->MaxDamping) this->Alpha = this->MaxDamping;
    return force - velocity * this->Alpha;
  }
  /// The force the device will hold until the next step.
  void Held(const Vec3& force) noexcept { this->LastForce = force; }
  double ObservedEnergy() const { return this->Energy; }  // N·mm (mJ)
  double AddedDamping() const { return this->Alpha; }     // N·s/mm this tick

 private:
  double MaxDamping;
  double Energy = 0;
  double Alpha = 0;
  Vec3 LastPosition, LastForce;
};

}  // namespace rp
