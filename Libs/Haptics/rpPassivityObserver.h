#pragma once
// Passivity observer / controller (Hannaford & Ryu, IEEE TRO 2002). It integrates the energy the
// virtual environment absorbed from the user, using the force actually held by the device over
// each period (zero-order hold) and the displacement over that period:
//     E(n) = E(n−1) − F(n−1)·(x(n) − x(n−1)).
// A passive environment keeps E ≥ 0. The virtual springs hold energy U = Σ ½ k |Δd|² that they
// will give back as the user withdraws, so the controller acts as soon as E − U < 0 (more stored
// than was ever absorbed: a sampling loss, e.g. a servo stall held a stale force while the
// user pressed on), while there is still travel left to dissipate it: it adds the damping
// α = −(E − U) / (|v|² T) (capped), opposing the current velocity. With U = 0 this is Hannaford
// & Ryu's controller. Plain arithmetic, no allocation.
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
  /// `force` plus the damping that dissipates a deficit E − stored < 0 at `velocity` (capped).
  Vec3 Correct(const Vec3& velocity, const Vec3& force, double period, double stored = 0) noexcept {
    this->Alpha = 0;
    const double v2 = Norm2(velocity);
    const double available = this->Energy - stored;
    if (available >= 0 || v2 <= 1e-12 || period <= 0) return force;
    this->Alpha = -available / (v2 * period);
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
