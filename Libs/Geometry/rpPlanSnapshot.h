#pragma once
// A plan as immutable plain data for the real-time code (the haptic and drilling servos' virtual
// fixtures, navigation read-outs): what they read instead of the scene's plan nodes, which belong
// to the main thread (DESIGN.md, "Threads and the scene"). World RAS, mm. Built on the main thread
// from the scene (Planning module: vtkRPPlanningLogic::MakePlanSnapshot) and handed over as
// std::shared_ptr<const PlanSnapshot>, swapped atomically like the haptic scene; nothing in it
// changes after it is built, so any thread may read it. The strings are for messages only.
#include <memory>
#include <string>
#include <vector>

#include "rpBVH.h"
#include "rpMeshSignedDistance.h"
#include "rpTriangleMesh.h"
#include "rpVec3.h"

namespace rp {

/// A planned trajectory (or screw): the tool's axis from entry to target.
struct TrajectorySnapshot {
  std::string NodeID, Name;
  Vec3 Entry, Target;
  double ToolDiameterMm = 0;
  /// A screw: its diameter and length (tip at the target, shaft towards the entry) and head.
  bool IsScrew = false;
  double ScrewDiameterMm = 0, ScrewLengthMm = 0, HeadDiameterMm = 0, HeadLengthMm = 0;

  double LengthMm() const { return Norm(this->Target - this->Entry); }
  /// Unit direction entry -> target (zero for a zero-length plan, which the builder refuses).
  Vec3 Direction() const { return Normalized(this->Target - this->Entry); }
};

/// A planned cut: a plane through Origin with unit Normal (and in-plane XAxis, size for display).
struct CutPlaneSnapshot {
  std::string NodeID, Name;
  Vec3 Origin, Normal, XAxis;
  double SizeMm[2] = {0, 0};
  /// Signed distance of p from the plane (positive on the normal's side).
  double SignedDistance(const Vec3& p) const { return Dot(p - this->Origin, this->Normal); }
};

/// A structure at risk (a model or segment flagged protected, rpProtection.h): its closed surface
/// in world RAS with a BVH for closest-point and segment queries, and the safety margin.
struct StructureAtRiskSnapshot {
  std::string NodeID, SegmentID, Name;  // SegmentID: "" for a model
  double SafetyMarginMm = 0;
  std::shared_ptr<const TriangleMesh> Surface;
  std::shared_ptr<const BVH> Tree;
  /// Signed distance (negative inside) when the surface is closed and manifold; null otherwise
  /// (then only the unsigned distance of Tree is known).
  std::shared_ptr<const MeshSignedDistance> Signed;
};

struct PlanSnapshot {
  std::vector<TrajectorySnapshot> Trajectories;  // complete ones only
  std::vector<CutPlaneSnapshot> Planes;          // placed ones only
  std::vector<StructureAtRiskSnapshot> StructuresAtRisk;

  /// By node ID or name; nullptr when absent.
  const TrajectorySnapshot* FindTrajectory(const std::string& idOrName) const {
    for (const auto& t : this->Trajectories)
      if (t.NodeID == idOrName || t.Name == idOrName) return &t;
    return nullptr;
  }
  const CutPlaneSnapshot* FindPlane(const std::string& idOrName) const {
    for (const auto& p : this->Planes)
      if (p.NodeID == idOrName || p.Name == idOrName) return &p;
    return nullptr;
  }
};

}  // namespace rp
