#pragma once
// A hand to test guidance with: it holds the simulated device's stylus and means to follow a
// scripted path, with physiological tremor (8–12 Hz) and a slow drift on top, seeded and
// reproducible; the device's force pushes it off that path as it would push a real hand.
//
// Where the hand means to be:   x_i(t) = path(t) + tremor(t) + drift(t)
//   tremor: nine sinusoids (three per axis) at frequencies drawn in 8–12 Hz with random phases,
//           scaled so the tremor's RMS displacement (3-D) is TremorMm;
//   drift:  a constant speed DriftMmPerS whose direction turns slowly (a full turn in
//           DriftPeriodS, 10 s) in a random plane, starting at 0: about DriftMmPerS·t for the
//           first seconds, never farther than DriftMmPerS·DriftPeriodS/π;
//   all in closed form of t (any tick order gives the same hand), from one seed (splitmix64).
// Where the stylus tip is: a mass pulled to x_i by the hand's spring and damper, stiffer along the
// stylus's shaft (a surgeon pushes a drill firmly along it) than across it (and holds it lightly
// there), damped by the device's own mechanism, and pushed by the device's force (zero-order hold
// between ticks, integrated in sub-steps). Plain C++: Step() never allocates.
#include <cstdint>

#include "rpHapticDevice.h"

namespace rp {

struct HandNoise {
  double TremorMm = 0;       // RMS tremor displacement
  double TremorMinHz = 8, TremorMaxHz = 12;
  double DriftMmPerS = 0;    // drift speed
  double DriftPeriodS = 10;  // a full turn of the drift's direction (a slow postural sway, 0.1 Hz)
  uint64_t Seed = 1;
};

/// Tremor and drift as closed forms of time.
class HandNoiseField {
 public:
  explicit HandNoiseField(const HandNoise& noise = {});
  Vec3 Tremor(double t) const noexcept;
  Vec3 Drift(double t) const noexcept;
  Vec3 Offset(double t) const noexcept { return this->Tremor(t) + this->Drift(t); }
  const HandNoise& Settings() const { return this->Noise; }

 private:
  static constexpr int Components = 3;  // sinusoids per axis
  HandNoise Noise;
  double Amplitude = 0;
  double Frequency[3][Components] = {}, Phase[3][Components] = {};
  Vec3 DriftA, DriftB;  // orthonormal: the drift's plane
  double DriftPhase = 0;
};

/// The hand's mechanics (SI-friendly units: kg, N/mm, N·s/mm).
struct HandImpedance {
  double MassKg = 0.1;                 // fingers, hand and the device's end effector
  double AxialStiffness = 0.6;         // N/mm along the stylus's shaft: the surgeon pushes the drill
  double LateralStiffness = 0.1;       // N/mm across it: a light precision grip that lets a guide lead
  double AxialDamping = 0.011;         // N·s/mm (about 0.7 of critical with the mass)
  double LateralDamping = 0.0044;      // N·s/mm
  int SubSteps = 10;                   // integration steps per servo tick
};

/// The hand's state and its integration (servo thread).
class SimulatedHand {
 public:
  SimulatedHand(const HandNoise& noise, const HandImpedance& impedance, double deviceDamping);
  /// Puts the stylus where the hand means to be at `time`, at rest relative to it.
  void Reset(double time, const Pose& intent, const Vec3& intentVelocity) noexcept;
  /// Advances to `time` with `force` (N, device frame) held since the last step; `intent` is the
  /// scripted pose at `time` (the noise is added here). Returns the stylus pose; `velocity` mm/s.
  Pose Step(double time, const Pose& intent, const Vec3& intentVelocity, const Vec3& force, Vec3& velocity) noexcept;
  bool Started() const { return this->HasState; }
  const HandNoiseField& Noise() const { return this->Field; }
  /// Where the hand means the tip to be at the last step (path + tremor + drift).
  const Vec3& Intended() const { return this->Target; }

 private:
  HandNoiseField Field;
  HandImpedance Mechanics;
  double DeviceDamping;  // N·s/mm, to the ground
  bool HasState = false;
  double Time = 0;
  Vec3 Position, Velocity;     // mm, mm/s
  Vec3 Target, TargetVelocity;
  Vec3 Shaft{0, 0, 1};         // unit, device frame
};

}  // namespace rp
