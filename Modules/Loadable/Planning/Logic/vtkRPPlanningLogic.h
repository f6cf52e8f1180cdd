#ifndef vtkRPPlanningLogic_h
#define vtkRPPlanningLogic_h
// Planning logic (no Qt, testable headless): what the Planning module does to the scene, called
// by its panel, `roboplan plan` and the demo alike. Plans are scene nodes (Libs/MRML:
// vtkRPTrajectoryNode, vtkRPScrewNode, vtkRPCutPlaneNode); structures at risk are models and
// segments flagged protected (rpProtection.h). This logic finds them, meshes protected segments
// once (cached until the segmentation changes), and hands the plan to real-time code as an
// immutable snapshot (rpPlanSnapshot.h). Main thread only (it owns no thread).
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include <vtkObject.h>
#include <vtkSmartPointer.h>

#include "rpCutFigures.h"
#include "rpMaterial.h"
#include "rpPlanFixtures.h"
#include "rpPlanSnapshot.h"
#include "rpPlanningInputs.h"
#include "rpSegment.h"
#include "rpTrajectoryFigures.h"
#include "rpTrajectoryProposal.h"

class vtkPolyData;
class vtkRPCutPlaneNode;
class vtkRPModelNode;
class vtkRPNode;
class vtkRPPlanNode;
class vtkRPScalarVolumeNode;
class vtkRPScene;
class vtkRPScrewNode;
class vtkRPSegmentationNode;
class vtkRPTrajectoryNode;

class vtkRPPlanningLogic : public vtkObject {
 public:
  static vtkRPPlanningLogic* New();
  vtkTypeMacro(vtkRPPlanningLogic, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  void SetScene(vtkRPScene* scene) { this->Scene = scene; }
  vtkRPScene* GetScene() const { return this->Scene; }

  /// A structure at risk of the scene: a protected model, or a protected segment of a
  /// segmentation (SegmentID set).
  struct StructureAtRisk {
    vtkRPNode* Node = nullptr;
    std::string SegmentID;
    std::string Name;  // the model's name, or the segment's
    double SafetyMarginMm = 0;
  };
  /// Every protected model and protected segment, in scene order.
  std::vector<StructureAtRisk> GetStructuresAtRisk() const;
  /// The structure's closed surface in world RAS: a model's polydata under its transforms, a
  /// segment meshed as the segment models are (rp::LabelmapToMesh, cached). Null with `error`
  /// naming the structure when it has no surface (an empty model or segment).
  std::shared_ptr<const rp::TriangleMesh> GetStructureSurface(const StructureAtRisk& structure, std::string& error);
  /// Every structure at risk with its surface and BVH (rebuilt only when one of them changed).
  bool GetStructuresAtRiskSnapshot(std::vector<rp::StructureAtRiskSnapshot>& structures, std::string& error);

  // ---- the patient's data the figures read
  /// The material table (bone HU ranges, bone tissue classes); materials.json by default.
  void SetMaterials(const rp::MaterialTable& materials) { this->Materials = materials; }
  const rp::MaterialTable& GetMaterials();
  /// The CT and the segmentation (either may be null); `boneSegments` as rp::PlanningInputs.
  bool SetPatientData(vtkRPScalarVolumeNode* ct, vtkRPSegmentationNode* segmentation, std::string& error,
                      const std::vector<std::string>& boneSegments = {});
  vtkRPScalarVolumeNode* GetCT() const { return this->CT; }
  vtkRPSegmentationNode* GetSegmentation() const { return this->Segmentation; }
  const rp::PlanningInputs& GetInputs() const { return this->Inputs; }

  // ---- a trajectory's or screw's figures
  /// Everything the Planning README lists, for one complete trajectory, with the scene's
  /// structures at risk. False with `error` on bad input, naming it: a zero-length trajectory, a
  /// target outside the CT, an entry inside a structure at risk, a screw longer than the bone
  /// along its axis, a plan made on another patient's CT.
  bool ComputeFigures(vtkRPTrajectoryNode* trajectory, rp::TrajectoryFigures& figures, std::string& error);
  /// The trajectory as plain data in world RAS (false when incomplete).
  static bool TrajectoryOf(vtkRPTrajectoryNode* node, rp::TrajectorySnapshot& trajectory);

  // ---- proposing a trajectory
  struct ProposalOptions {
    double ToolDiameterMm = 2;
    double SpacingMm = 1;          // candidates: the region's surface refined to this edge length
    double SphereCenter[3] = {0, 0, 0};
    double SphereRadiusMm = 0;     // > 0: only the region within this sphere
    bool StayInBone = false;
    int Best = 5;
    int Threads = 2;
  };
  /// The entry region: a surface patch (a model), or a segment's surface; restricted to a sphere
  /// when asked. Its points are the candidates (kept until the region changes).
  bool SetEntryRegion(vtkPolyData* regionWorld, const ProposalOptions& options, std::string& error);
  bool SetEntryRegion(vtkRPModelNode* region, const ProposalOptions& options, std::string& error);
  bool SetEntryRegionFromSegment(vtkRPSegmentationNode* segmentation, const std::string& segment,
                                 const ProposalOptions& options, std::string& error);
  const std::vector<rp::Vec3>& GetCandidates() const { return this->Candidates; }
  /// Scores every candidate entry towards `targetRAS` against the scene's structures at risk.
  bool Propose(const double targetRAS[3], const ProposalOptions& options, rp::ProposalResult& result, std::string& error);
  /// The entry region coloured by clearance: a model node ("<name>", attribute "Planning.riskMap"
  /// = "clearanceMm") whose points carry the scalar "clearanceMm" (and "slackMm"), added to the
  /// scene or updated.
  vtkRPModelNode* UpdateRiskMap(const rp::ProposalResult& result, const std::string& name = "Risk map");
  /// The region's surface with the scores as point scalars (what the risk map model shows).
  vtkSmartPointer<vtkPolyData> RiskMapPolyData(const rp::ProposalResult& result) const;

  // ---- cut planes
  struct BoneCut {
    std::string Bone;
    rp::CutFigures Figures;
  };
  /// The bone volume on each side of the plane and the cut's area, per bone: each bone segment
  /// of the segmentation, else each bone model, else the CT's bone (threshold) as one.
  bool ComputeCut(vtkRPCutPlaneNode* plane, std::vector<BoneCut>& cuts, std::string& error);

  // ---- screws
  /// The screw's closed surface (rp::MakeScrewMesh) as a model node, created the first time and
  /// referenced by the screw ("screwModel"), updated when the screw changed.
  vtkRPModelNode* UpdateScrewModel(vtkRPScrewNode* screw);

  // ---- whose plan
  /// The identity of a CT for a plan's PlannedOn: its DICOM series and frame of reference when
  /// the node carries them, and its voxel grid (dimensions, IJK-to-RAS).
  static std::string VolumeIdentity(vtkRPScalarVolumeNode* volume);
  /// False with `error` when the plan was made on another CT than `volume`.
  static bool CheckPlannedOn(vtkRPPlanNode* plan, vtkRPScalarVolumeNode* volume, std::string& error);

  /// The scene's plan as immutable plain data (complete trajectories and screws, placed cut
  /// planes, every structure at risk with its surface and BVH) for the servo threads. Null with
  /// `error` when a structure at risk has no surface or a trajectory has zero length: a plan that
  /// cannot be guided is not handed over in part.
  std::shared_ptr<const rp::PlanSnapshot> MakePlanSnapshot(std::string& error);
  /// The virtual fixtures `choice` switches on, built from that snapshot (rp::BuildPlanFixtures;
  /// a surface constraint on choice.SurfaceModelNode takes that model's surface in world RAS): what
  /// the Haptics and Drilling logics hand their servos. An empty set when none is on; null with
  /// `error` naming what a chosen fixture lacks.
  std::shared_ptr<const rp::FixtureSet> MakePlanFixtures(rp::PlanFixtureChoice choice, std::string& error);

 protected:
  vtkRPPlanningLogic() = default;
  ~vtkRPPlanningLogic() override = default;

 private:
  vtkRPPlanningLogic(const vtkRPPlanningLogic&) = delete;
  void operator=(const vtkRPPlanningLogic&) = delete;
  bool AddStructures(rp::PlanSnapshot& plan, std::string& error);
  std::shared_ptr<const rp::TriangleMesh> SegmentSurface(vtkRPSegmentationNode* segmentation, const rp::Segment& segment,
                                                        std::string& error);
  bool BoneSurfaces(std::vector<std::pair<std::string, std::shared_ptr<const rp::TriangleMesh>>>& bones, std::string& error);
  bool ThresholdBoneSurface(std::vector<std::pair<std::string, std::shared_ptr<const rp::TriangleMesh>>>& bones,
                            std::string& error);
  bool CheckTrajectory(vtkRPTrajectoryNode* node, const rp::TrajectorySnapshot& plan,
                       const std::vector<rp::StructureAtRiskSnapshot>& structures, std::string& error);
  bool CheckScrewFits(const rp::TrajectorySnapshot& plan, std::string& error);
  vtkRPScene* Scene = nullptr;  // not owned (the host owns the scene)
  rp::MaterialTable Materials;
  vtkRPScalarVolumeNode* CT = nullptr;             // not owned
  vtkRPSegmentationNode* Segmentation = nullptr;  // not owned
  rp::PlanningInputs Inputs;
  // The entry region and its candidates.
  vtkSmartPointer<vtkPolyData> Region;
  std::vector<rp::Vec3> Candidates;
  std::vector<uint32_t> CandidateOrder;
  double CandidateSpacing = 0;
  // Structures at risk as last snapshotted, and when (the scene's structures may change).
  std::vector<rp::StructureAtRiskSnapshot> StructureCache;
  unsigned long StructureCacheTime = 0;
  // Meshed segments: (segmentation node ID, segment ID) -> (the node's and its transform's
  // modification times when meshed, the surface).
  struct CachedSurface {
    unsigned long NodeTime = 0, TransformTime = 0;
    std::shared_ptr<const rp::TriangleMesh> Surface;
  };
  std::map<std::pair<std::string, std::string>, CachedSurface> SegmentSurfaces;
};

#endif
