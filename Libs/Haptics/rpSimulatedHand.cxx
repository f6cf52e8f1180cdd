#include "rpSimulatedHand.h"

#include <algorithm>
#include <cmath>

namespace rp {

namespace {
// splitmix64: a small, portable generator (the same numbers on every platform and library).
struct SplitMix {
  uint64_t State;
  uint64_t Next() {
    uint64_t z = (this->State += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double Uniform() { return static_cast<double>(this->Next() >> 11) * 0x1.0p-53; }  // [0, 1)
};

Vec3 RandomUnit(SplitMix& random) {
  const double z = 2 * random.Uniform() - 1, a = 2 * M_PI * random.Uniform();
  const double r = std::sqrt(std::max(0.0, 1 - z * z));
  return {r * std::cos(a), r * std::sin(a), z};
}
}  // namespace

HandNoiseField::HandNoiseField(const HandNoise& noise) : Noise(noise) {
  SplitMix random{noise.Seed};
  // 3 axes × Components sinusoids of amplitude a: RMS displacement sqrt(9 a² / 2).
  this->Amplitude = noise.TremorMm * std::sqrt(2.0 / (3.0 * Components));
  for (int axis = 0; axis < 3; ++axis)
    for (int c = 0; c < Components; ++c) {
      this->Frequency[axis][c] = noise.TremorMinHz + (noise.TremorMaxHz - noise.TremorMinHz) * random.Uniform();
      this->Phase[axis][c] = 2 * M_PI * random.Uniform();
    }
  this->DriftA = RandomUnit(random);
  Vec3 other = RandomUnit(random);
  while (Norm(Cross(this->DriftA, other)) < 0.1) other = RandomUnit(random);
  this->DriftB = Normalized(other - this->DriftA * Dot(other, this->DriftA));
  this->DriftPhase = 2 * M_PI * random.Uniform();
}

Vec3 HandNoiseField::Tremor(double t) const noexcept {
  Vec3 out;
  if (this->Amplitude <= 0) return out;
  for (int axis = 0; axis < 3; ++axis) {
    double sum = 0;
    for (int c = 0; c < Components; ++c) sum += std::sin(2 * M_PI * this->Frequency[axis][c] * t + this->Phase[axis][c]);
    out[axis] = this->Amplitude * sum;
  }
  return out;
}

Vec3 HandNoiseField::Drift(double t) const noexcept {
  if (this->Noise.DriftMmPerS <= 0 || this->Noise.DriftPeriodS <= 0) return {};
  // Velocity D·(cos(ωt+φ) a + sin(ωt+φ) b): constant speed D, direction turning at ω.
  const double w = 2 * M_PI / this->Noise.DriftPeriodS, r = this->Noise.DriftMmPerS / w, p = this->DriftPhase;
  auto at = [&](double time) {
    return this->DriftA * (r * std::sin(w * time + p)) - this->DriftB * (r * std::cos(w * time + p));
  };
  return at(t) - at(0);
}

SimulatedHand::SimulatedHand(const HandNoise& noise, const HandImpedance& impedance, double deviceDamping)
    : Field(noise), Mechanics(impedance), DeviceDamping(std::max(0.0, deviceDamping)) {}

void SimulatedHand::Reset(double time, const Pose& intent, const Vec3& intentVelocity) noexcept {
  this->Time = time;
  this->Target = intent.T + this->Field.Offset(time);
  this->TargetVelocity = intentVelocity;
  this->Position = this->Target;
  this->Velocity = intentVelocity;
  this->Shaft = Normalized(Vec3{intent.R[2], intent.R[5], intent.R[8]});  // the stylus's +z in the device frame
  this->HasState = true;
}

Pose SimulatedHand::Step(double time, const Pose& intent, const Vec3& intentVelocity, const Vec3& force,
                         Vec3& velocity) noexcept {
  if (!this->HasState) this->Reset(time, intent, intentVelocity);
  const Vec3 target = intent.T + this->Field.Offset(time);
  const double span = time - this->Time;
  if (span > 0) {
    // Target velocity over the tick (the path's plus the noise's, by difference).
    this->TargetVelocity = (target - this->Target) / span;
    this->Shaft = Norm2(Vec3{intent.R[2], intent.R[5], intent.R[8]}) > 0
                      ? Normalized(Vec3{intent.R[2], intent.R[5], intent.R[8]})
                      : this->Shaft;
    const int steps = std::max(1, this->Mechanics.SubSteps);
    const double h = span / steps;
    const double mass = this->Mechanics.MassKg * 1e-3;  // N per (mm/s²): 1 kg·mm/s² = 1e-3 N
    for (int s = 1; s <= steps; ++s) {
      // The hand's target moves linearly over the tick.
      const Vec3 goal = this->Target + (target - this->Target) * (static_cast<double>(s) / steps);
      const Vec3 stretch = goal - this->Position, relative = this->TargetVelocity - this->Velocity;
      const double axialStretch = Dot(stretch, this->Shaft), axialRelative = Dot(relative, this->Shaft);
      const Vec3 hand = this->Shaft * (this->Mechanics.AxialStiffness * axialStretch +
                                       this->Mechanics.AxialDamping * axialRelative) +
                        (stretch - this->Shaft * axialStretch) * this->Mechanics.LateralStiffness +
                        (relative - this->Shaft * axialRelative) * this->Mechanics.LateralDamping;
      const Vec3 total = hand + force - this->Velocity * this->DeviceDamping;
      this->Velocity += total * (h / mass);  // semi-implicit Euler: velocity first
      this->Position += this->Velocity * h;
    }
    this->Target = target;
    this->Time = time;
  }
  Pose pose = intent;
  pose.T = this->Position;
  velocity = this->Velocity;
  return pose;
}

}  // namespace rp
