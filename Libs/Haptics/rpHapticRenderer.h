#pragma once
// Force for a multi-point tool (seed eq. 1–6): one god-object proxy per tool point (tip plus
// points along the shaft), a spring-damper per contact with the contacted tissue's k_i, b_i
//     F_i = k_i (x_proxy,i − x_hip,i) + b_i (v_proxy,i − v_hip,i)          (eq. 1–3)
// summed over contacts (eq. 4–5), gains limited to the device's passive region, a passivity
// observer, and the clamp of eq. 6 that keeps the direction: |F| > Fmax → F·Fmax/|F|.
// (The damping term opposes the HIP's motion relative to the proxy: the seed's eq. 2 writes
// −b·Δv with Δv = v_proxy − v_probe, which would inject energy; we use the dissipative sign.)
// Virtual fixtures (rpFixtureRenderer.h) act beside the tissue: their walls hold the tool back
// before it touches tissue (the tissue proxies see the tool where the walls let it go), their
// forces join the tissue's inside the same passivity observer and clamp, and the tissue's gains
// share the device's passive budget with theirs.
// Not thread-aware: the servo task owns one. Update() never allocates.
#include "rpFixtureRenderer.h"
#include "rpGodObjectProxy.h"
#include "rpHapticDevice.h"
#include "rpPassivityObserver.h"
#include "rpStability.h"

namespace rp {

constexpr int MaxToolPoints = 8;
/// The way the tool points in the stylus frame: its shaft runs from the tip along +z (the tool
/// points of a multi-point tool), so the tip leads along −z.
constexpr Vec3 ToolForward{0, 0, -1};

struct RendererOptions {
  bool Friction = true;
  bool ForceShading = true;
  bool LimitGains = true;         // Colgate-Schenkel + nominal device limits
  bool PassivityControl = true;
  double Period = 0.001;          // s: the servo period the passivity limits assume (measured)
  double WorkspaceScale = 1.0;    // scene mm per device mm
};

struct PointContact {
  Vec3 Hip, Proxy, Force;
  bool InContact = false;
  int Planes = 0;
  uint16_t Label = 0;
  double Depth = 0;  // |proxy − HIP| along the contact normal (mm)
};

struct RenderOutput {
  Vec3 Tip;             // the device's tool tip (scene frame); Points[0].Hip is where the walls let it go
  Vec3 Force;           // after gain limits, passivity control and the clamp (N, scene frame)
  Vec3 Torque;          // N·mm, the fixtures' (axis guidance), within the device's MaxTorque
  Vec3 FixtureForce;    // the fixtures' share of Force before passivity and the clamp
  Vec3 UnclampedForce;  // eq. 4 result before the clamp
  bool Clamped = false;
  bool StallLimited = false;  // after a servo stall the force was held to what the motion justifies
  int Contacts = 0;
  int PrimaryPoint = -1;  // the deepest contact
  GainLimits Gains;
  double ObservedEnergy = 0, AddedDamping = 0;
  int NumberOfPoints = 0;
  PointContact Points[MaxToolPoints];
};

class HapticRenderer {
 public:
  HapticRenderer();
  /// Tool points in the stylus frame (mm); point 0 is the tip (the HIP). At most MaxToolPoints.
  bool SetToolPoints(const Vec3* points, int count);
  void SetOptions(const RendererOptions& options) { this->Options = options; }
  const RendererOptions& GetOptions() const { return this->Options; }
  void SetDevice(const DeviceInfo& device);
  void SetScene(const HapticScene* scene) noexcept { this->Scene = scene; }
  /// The virtual fixtures for this tick (nullptr: none); servo thread, from a FixtureExchange.
  void SetFixtures(const FixtureSet* fixtures) noexcept { this->FixtureSnapshot = fixtures; }
  /// The tool's radius at the tip for the walls (a burr's; 0 for a stylus point).
  void SetToolRadius(double radius) noexcept { this->ToolRadius = radius; }
  /// The fixtures this tick (goal, per-fixture reports).
  const FixtureOutput& Fixtures() const { return this->Guides.Output(); }
  /// Puts every proxy on its HIP (no contact) for this stylus pose (scene frame).
  void Reset(const Pose& stylusToScene) noexcept;
  /// One servo tick: stylus pose in the scene frame; `elapsed` the time since the previous tick
  /// (s; ≤ 0: Options.Period). Velocities use the elapsed time. After a stall (elapsed above
  /// 1.5 periods) the force may grow over the previous one by no more than the contacts'
  /// rendered stiffness times the distance the tool moved: the hand felt a stale force during
  /// the stall, and a damping or passivity term estimated over it must not come back as a kick.
  /// With fixtures, the tool is first moved to where their walls let it go (Output().Tip is the
  /// device's own, Points[0].Hip the tool's as the tissue sees it).
  const RenderOutput& Update(const Pose& stylusToScene, double elapsed = 0) noexcept;
  const RenderOutput& Output() const { return this->Out; }

 private:
  RendererOptions Options;
  DeviceInfo Device;
  double MaxForce = 3.3;
  const HapticScene* Scene = nullptr;
  const FixtureSet* FixtureSnapshot = nullptr;
  FixtureRenderer Guides;
  double ToolRadius = 0;
  int PointCount = 1;
  Vec3 ToolPoints[MaxToolPoints];
  GodObjectProxy Proxies[MaxToolPoints];
  Vec3 LastHip[MaxToolPoints], LastProxy[MaxToolPoints];
  bool Initialized = false;
  bool WasInContact = false;
  Vec3 LastTip;
  PassivityObserver Observer;
  RenderOutput Out;
};

}  // namespace rp
