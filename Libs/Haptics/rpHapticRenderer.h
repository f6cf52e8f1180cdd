#pragma once
// Force for a multi-point tool (seed eq. 1–6): one god-object proxy per tool point (tip plus
// points along the shaft), a spring-damper per contact with the contacted tissue's k_i, b_i
//     F_i = k_i (x_proxy,i − x_hip,i) + b_i (v_proxy,i − v_hip,i)          (eq. 1–3)
// summed over contacts (eq. 4–5), gains limited to the device's passive region, a passivity
// observer, and the clamp of eq. 6 that keeps the direction: |F| > Fmax → F·Fmax/|F|.
// (The damping term opposes the HIP's motion relative to the proxy: the seed's eq. 2 writes
// −b·Δv with Δv = v_proxy − v_probe, which would inject energy; we use the dissipative sign.)
// Virtual fixtures (rpToolConstraint.h): their walls first hold the tool back (the tissue proxies
// see the tool where the walls let it go, and get the device's passive budget the fixtures left),
// then their force joins the contacts' before the passivity observer and the clamp.
// Not thread-aware: the servo task owns one. Update() never allocates.
#include "rpGodObjectProxy.h"
#include "rpHapticDevice.h"
#include "rpPassivityObserver.h"
#include "rpStability.h"
#include "rpToolConstraint.h"

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
  Vec3 Tip;             // the device's tool tip (scene frame)
  Vec3 Goal;            // where the constraints' walls let it go (Points[0].Hip: the tool as the tissue sees it)
  Vec3 Force;           // after gain limits, passivity control and the clamp (N, scene frame)
  Vec3 UnclampedForce;  // eq. 4 result before the clamp
  bool Clamped = false;
  bool StallLimited = false;  // after a servo stall the force was held to what the motion justifies
  int Contacts = 0;
  int PrimaryPoint = -1;  // the deepest contact
  GainLimits Gains;
  ConstraintForce Constraint;  // what the virtual fixtures added (included in Force)
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
  /// Puts every proxy on its HIP (no contact) for this stylus pose (scene frame).
  void Reset(const Pose& stylusToScene) noexcept;
  /// One servo tick: stylus pose in the scene frame; `elapsed` the time since the previous tick
  /// (s; ≤ 0: Options.Period). Velocities use the elapsed time. After a stall (elapsed above
  /// 1.5 periods) the force may grow over the previous one by no more than the contacts'
  /// rendered stiffness times the distance the tool moved: the hand felt a stale force during
  /// the stall, and a damping or passivity term estimated over it must not come back as a kick.
  /// `constraints` (virtual fixtures, rpToolConstraint.h) act on the tip beside the contacts,
  /// inside the passivity observer, the stall bound and the clamp.
  const RenderOutput& Update(const Pose& stylusToScene, double elapsed = 0, ToolConstraints* constraints = nullptr) noexcept;
  const RenderOutput& Output() const { return this->Out; }

 private:
  /// The tool as the virtual fixtures see it this tick (before the contacts).
  ConstraintContext ToolContext(const Pose& device, double dt, double period) const noexcept;
  /// The virtual fixtures' force this tick (after the contacts' pass 2).
  ConstraintForce EvaluateConstraints(ToolConstraints& constraints, ConstraintContext& tool) noexcept;

  RendererOptions Options;
  DeviceInfo Device;
  double MaxForce = 3.3;
  const HapticScene* Scene = nullptr;
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
