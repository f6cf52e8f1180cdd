#include "rpDrillServo.h"

#include <algorithm>
#include <cmath>

namespace rp {

DrillServo::DrillServo(HapticDevice& device, DrillVolume& volume, const DrillServoOptions& options)
    : Tool(device), Volume(volume), Settings(options), Cut(volume) {
  this->Render.SetDevice(device.Info());
  this->Mesh.SetDevice(device.Info());
  this->ControlValue.Publish(DrillControl{});
}

void DrillServo::PlaceBurr(const Vec3& center, const DrillControl& control) {
  this->ControlValue.Publish(control);
  this->Render.Reset(center);
  this->HasCutCenter = this->HasLastCut = false;
  if (control.BurrOn) {
    this->Cut.BeginStroke();
    const bool refused = this->Cut.Cut(center, control.Radius).Refused;
    this->CutCenter = this->LastCut = center;
    this->LastCutRadius = control.Radius;
    this->HasCutCenter = true;
    this->HasLastCut = !refused;
  }
  this->WasOn = control.BurrOn;
  this->Placed = true;
}

double DrillServo::MaxCutLead(double rpm, double period) const {
  double softest = HUGE_VAL;
  for (const Material& m : this->Volume.Materials())
    if (m.Hardness > 0) softest = std::min(softest, m.Hardness);
  if (!(softest < HUGE_VAL)) return 0;
  return this->Settings.FeedRate * std::max(0.0, rpm) / this->Settings.ReferenceRpm / softest * period *
         std::max(1, this->Settings.CutSlices);
}

void DrillServo::ServoStarted() noexcept {
  this->First = true;
  this->Trips = 0;
  this->Tool.WriteForce(Vec3{});
}

void DrillServo::ServoStopping() noexcept {
  this->Tool.WriteForce(Vec3{});
  this->Cut.EndStroke();
}

void DrillServo::Publish(const TickInfo& tick, uint32_t flags) noexcept {
  DrillState& s = this->Scratch;
  this->StateValue.Publish(s);
  if (!this->Recording.load(std::memory_order_relaxed)) return;
  DrillRecord r;
  r.Time = tick.Time;
  r.Hip = s.Hip;
  r.Proxy = s.Proxy;
  r.Force = s.Force;
  r.Radius = static_cast<float>(s.Radius);
  r.RemovedTotalMm3 = static_cast<float>(s.RemovedTotalMm3);
  r.ProtectedDistance = static_cast<float>(s.ProtectedDistance);
  r.TickComputeUs = static_cast<float>(tick.PreviousComputeNs * 1e-3);
  r.Flags = flags;
  r.CutMaterial = s.CutMaterial;
  this->Log.TryPush(r);
}

// Requests from the main thread: undo the last stroke, reset the bone.
void DrillServo::ServeRequests() noexcept {
  const uint32_t undo = this->UndoRequests.load(std::memory_order_acquire);
  const uint32_t reset = this->ResetRequests.load(std::memory_order_acquire);
  if (reset != this->ResetSeen) {
    this->ResetSeen = reset;
    this->UndoSeen = undo;
    this->Cut.StartReset();
    this->HasCutCenter = this->HasLastCut = false;  // the bone around the last cut comes back
  } else if (undo != this->UndoSeen) {
    this->UndoSeen = undo;
    this->Cut.StartUndo();
    this->HasCutCenter = this->HasLastCut = false;
  }
  this->Cut.Step();
}

// The burr in contact with bone it may cut: advances the cut at the feed rate; true if the cut
// was refused (the protected structure).
bool DrillServo::CutAhead(const BurrForce& burr, const Vec3& hip, double radius, double rpm, double dt) noexcept {
  DrillState& s = this->Scratch;
  bool refused = false;
  const BurrContact& contact = burr.Contact;
  const Vec3 push = hip - burr.Proxy;
  const double distance = Norm(push);
  const double hardness = contact.CutHardness;  // of the bone ahead, weighted by contact
  const double maxForce = this->Render.Device().MaxForce > 0 ? this->Render.Device().MaxForce : 1.0;
  if (distance > 1e-9 && hardness > 0) {
    s.FeedMmPerS = this->Settings.FeedRate * std::min(1.0, Norm(burr.Force) / maxForce) *
                   std::max(0.0, rpm) / this->Settings.ReferenceRpm / hardness;
    // One cut carries CutSlices ticks' advance, carved over as many ticks.
    const int slices = std::max(1, this->Settings.CutSlices);
    const double step = s.FeedMmPerS * dt * slices;
    // The cut advances from the last one while the proxy keeps up with it (within a skin and
    // the cut in progress); from the proxy when it moved away (slid, pulled back) or the burr just touched.
    const double skin = BurrProxy::Skin * this->Volume.Spacing();
    if (!this->HasCutCenter || Norm(this->CutCenter - burr.Proxy) > 3 * skin + step)
      this->CutCenter = burr.Proxy;
    const Vec3 ahead = hip - this->CutCenter;
    const double advance = std::min(step, Norm(ahead));
    if (advance > 0) {
      const Vec3 center = this->CutCenter + ahead * (advance / Norm(ahead));
      // Only what the new sphere adds to the last one (the same burr, nothing restored since)
      // is visited: the difference of the two spheres, not the whole ball.
      Vec3 direction{};
      double moved = 0;
      if (this->HasLastCut && this->LastCutRadius == radius) {
        moved = Norm(center - this->LastCut);
        if (moved > 0) direction = (center - this->LastCut) / moved;
      }
      const CutResult cut = this->Cut.BeginCut(center, radius, direction, moved, slices);
      refused = cut.Refused;
      s.Cutting = this->CutRemoved = cut.Removed;
      this->CutFeed = s.FeedMmPerS;
      if (!refused) {
        this->CutCenter = this->LastCut = center;
        this->LastCutRadius = radius;
        this->HasCutCenter = this->HasLastCut = true;
      }
    }
  }
  return refused;
}

// Distance to the protected structure (burr surface to its surface). Last tick's closest point
// lies on the surface, so its distance from the proxy bounds this tick's: the search starts with
// that bound and skips the tree's farther boxes (still exact; from scratch, with the demo's PCL
// 13 mm away, this search was 17 % of the tunnel's drilling time, now 8 %).
void DrillServo::MeasureProtected(const Vec3& proxy, double radius) noexcept {
  DrillState& s = this->Scratch;
  if (this->Protected == nullptr || this->Protected->Empty()) return;
  ClosestPointHit hit;
  const double bound = this->HasProtectedPoint ? Norm(proxy - this->ProtectedPoint) * (1 + 1e-9) + 1e-9 : HUGE_VAL;
  if (this->Protected->ClosestPoint(proxy, bound, hit) || this->Protected->ClosestPoint(proxy, HUGE_VAL, hit)) {
    s.ProtectedDistance = std::sqrt(hit.Distance2) - radius;
    s.ClosestApproach = std::min(s.ClosestApproach, s.ProtectedDistance);
    this->ProtectedPoint = hit.Point;
    this->HasProtectedPoint = true;
  }
}

// The state the main thread reads; returns the record's flags.
uint32_t DrillServo::FillState(const BurrForce& burr, const Vec3& hip, const Vec3& force, double radius, bool on,
                               bool clamped, bool refused, double ramp) noexcept {
  DrillState& s = this->Scratch;
  const BurrContact& contact = burr.Contact;
  const auto& materials = this->Volume.Materials();
  s.Hip = hip;
  s.Proxy = burr.Proxy;
  s.Force = force;
  s.Radius = radius;
  s.BurrOn = on;
  s.Contact = contact.InContact;
  s.Embedded = contact.Embedded;
  s.Clamped = clamped;
  s.Restoring = this->Cut.Restoring();
  s.Material = contact.Material > 0 ? contact.Material - 1 : -1;
  s.CutMaterial = contact.CutMaterial > 0 ? contact.CutMaterial - 1 : -1;
  s.Depth = burr.Depth;
  for (size_t m = 0; m < materials.size(); ++m) s.RemovedMm3[m] = this->Cut.Removed(static_cast<int>(m));
  s.RemovedTotalMm3 = this->Cut.RemovedTotal();
  s.UndoableStrokes = this->Cut.UndoableStrokes();
  s.Strokes = this->Cut.StrokesStarted();
  s.LastStrokeLost = this->Cut.LastStrokeLost();
  s.WatchdogTrips = this->Trips;
  s.ObservedEnergy = burr.ObservedEnergy;
  s.Stiffness = burr.Stiffness;
  s.RampScale = ramp;
  s.PeakForce = std::max(s.PeakForce, Norm(force));
  s.Fixtures.CopyFrom(burr.Constraint.Fixtures);
  uint32_t flags = 0;
  if (on) flags |= DrillRecordFlags::BurrOn;
  if (s.Contact) flags |= DrillRecordFlags::Contact;
  if (s.Cutting) flags |= DrillRecordFlags::Cutting;
  if (refused) flags |= DrillRecordFlags::Refused;
  if (clamped) flags |= DrillRecordFlags::Clamped;
  if (s.Embedded) flags |= DrillRecordFlags::Embedded;
  return flags;
}

void DrillServo::Tick(const TickInfo& tick) noexcept {
  DrillState& s = this->Scratch;
  s.Time = tick.Time;
  s.Tick = tick.Index;
  DrillControl control;
  this->ControlValue.Read(control);
  ToolConstraints* constraints = AcquireConstraints(this->ConstraintSlots);
  const double dt = tick.Period > 0 ? tick.Period : 0.001;

  ToolSample tool;
  const bool ok = this->Tool.Read(tick.Time, tool);
  s.DeviceError = !ok;
  const double elapsed = this->Clock.Elapsed(tick, this->First, dt);
  if (!ok || tick.PreviousOverran) {
    // Watchdog: no force, no cutting, ramp in again.
    ++this->Trips;
    this->Clock.RestartRamp(tick.Time);
    this->Tool.WriteForce(Vec3{});
    s.Force = Vec3{};
    s.Cutting = false;
    s.RampScale = 0;
    s.WatchdogTrips = this->Trips;
    this->Publish(tick, DrillRecordFlags::Watchdog);
    return;
  }

  // Stylus (and burr centre) in the scene.
  const Pose& stylus = tool.StylusToScene;
  const double scale = this->Tool.WorkspaceScale();
  const Vec3 hip = stylus.Apply(this->Settings.BurrCenter);
  const double radius = std::clamp(control.Radius, 0.25, 10.0);
  if (this->First) {
    if (!this->Placed) this->Render.Reset(hip);
    this->Mesh.Reset(stylus);
    this->First = false;
    this->Placed = false;
  }

  this->ServeRequests();

  // Strokes follow the burr switch; a refused cut stops the burr until it is switched again.
  if (!control.BurrOn) s.Stopped = false;
  const bool on = control.BurrOn && !s.Stopped;
  if (!on && this->WasOn) this->Cut.EndStroke();
  if (on && !this->Cut.InStroke() && !this->Cut.Restoring()) this->Cut.BeginStroke();
  this->WasOn = on;

  // Forces: the other haptic models (mesh god-object) and the burr on the bone share the budget.
  RendererOptions meshOptions = this->Mesh.GetOptions();
  meshOptions.Period = dt;
  meshOptions.WorkspaceScale = scale;
  this->Mesh.SetOptions(meshOptions);
  this->Mesh.SetScene(this->SceneSlots.Acquire());
  const RenderOutput& meshOut = this->Mesh.Update(stylus, elapsed);
  BurrForceOptions burrOptions = this->Render.GetOptions();
  burrOptions.Period = dt;
  burrOptions.WorkspaceScale = scale;
  this->Render.SetOptions(burrOptions);
  const BurrForce& burr = this->Render.Update(this->Volume, hip, radius, meshOut.Contacts ? meshOut.Gains.Stiffness : 0.0,
                                             meshOut.Contacts ? meshOut.Gains.Damping : 0.0, elapsed, constraints, stylus);

  // Cutting.
  s.Cutting = false;
  s.FeedMmPerS = 0;
  const BurrContact& contact = burr.Contact;
  bool refused = false;
  if (this->Cut.CutPending()) {  // the next share of the cut in progress
    this->CutRemoved = this->Cut.ContinueCut().Removed || this->CutRemoved;
    s.Cutting = this->CutRemoved;
    s.FeedMmPerS = this->CutFeed;
  } else if (on && contact.InContact && !contact.Embedded && contact.CutMaterial > 0 && !this->Cut.Restoring() &&
             !burr.Constraint.ForbidCut) {
    refused = this->CutAhead(burr, burr.Goal, radius, control.Rpm, dt);  // towards where the walls let the burr go
  }
  if (!s.Cutting && !on) this->HasCutCenter = false;
  if (refused) {
    ++s.RefusedTicks;
    s.Stopped = true;
    this->Cut.EndStroke();
  }

  this->MeasureProtected(burr.Proxy, radius);
  s.Warning = s.ProtectedDistance < this->Settings.WarningDistance || s.Stopped;

  // Sum, clamp (eq. 6), ramp, send.
  Vec3 total = burr.Force + meshOut.Force;
  const double maxForce = this->Render.Device().MaxForce;
  const double magnitude = Norm(total);
  const bool clamped = burr.Clamped || meshOut.Clamped || magnitude > maxForce;
  if (magnitude > maxForce) total = total * (maxForce / magnitude);
  const double ramp = this->Clock.Ramp(tick.Time, this->Settings.RampSeconds);
  const Vec3 force = total * ramp;
  this->Tool.WriteForce(force);

  const uint32_t flags = this->FillState(burr, hip, force, radius, on, clamped, refused, ramp);
  this->Publish(tick, flags);
}

}  // namespace rp
