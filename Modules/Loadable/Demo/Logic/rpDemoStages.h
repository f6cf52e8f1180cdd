#pragma once
// The stages of the main job and the state they pass along. Each stage reads what earlier
// stages put in DemoState, adds nodes to the scene, figures and pictures to the report, and
// throws std::runtime_error with a message naming the problem when it cannot go on.
#include <array>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "rpDemo.h"
#include "rpToolDefinition.h"

class vtkRPScene;
class vtkRPScalarVolumeNode;
class vtkRPSegmentationNode;
class vtkImageData;
class vtkMatrix4x4;

namespace rp {

class Report;
class StageRunner;
struct KneePhantom;

struct DemoState {
  DemoOptions Options;
  std::string Output;  // absolute output folder
  rp::Report* Report = nullptr;
  rp::StageRunner* Runner = nullptr;
  vtkSmartPointer<vtkRPScene> Scene;
  std::shared_ptr<KneePhantom> Phantom;  // null with --data (no ground truth)
  vtkRPScalarVolumeNode* CT = nullptr;   // nodes in the scene
  vtkRPScalarVolumeNode* MR = nullptr;
  vtkRPSegmentationNode* Segmentation = nullptr;
  std::vector<std::string> BoneModelIDs, HapticModelIDs, DisplayModelIDs;
  std::map<std::string, std::string> DisplayModelIDOfSegment;  // segment ID → its display model's node ID
  std::string TrackerToRASID, StylusTipToStylusID, StylusToTrackerID;
  std::array<double, 3> StylusTip{};  // calibrated StylusTipToStylus offset
  // The knee's own axes for pictures (the phantom's; the scanner's for a user's CT, lateral
  // towards the fibula).
  std::array<double, 3> KneeLateral{{1, 0, 0}}, KneeAnterior{{0, 1, 0}};
  bool KneeAxesKnown = false;
  ToolDefinition StylusTruth;         // the simulated stylus (its true tip offset)
  // The Plan stage's nodes (IDs; "" when it made none): the tibial tunnel and the screw.
  std::string TunnelPlanID, ScrewPlanID;
  bool HasGroundTruth() const { return static_cast<bool>(this->Phantom); }
};

struct DemoStage {
  std::string Name;
  std::function<void(DemoState&)> Run;
};

/// Stages implemented in their own files.
void ExploreHaptically(DemoState& state);
void CalibrateStylus(DemoState& state);
void RegisterPatient(DemoState& state);
void Navigate(DemoState& state);
void MeasureSpeedAgainstAccuracy(DemoState& state);
void PlanTunnelAndScrew(DemoState& state);
void DrillTibialTunnel(DemoState& state);
void ExecutePlans(DemoState& state);
/// The tibia's drillable voxels (mm): the tunnel is drilled and the plans are executed on it.
constexpr double DemoDrillVoxelMm = 0.3;
/// Whether pictures can be drawn in this run (screenshots on, a display); else why not.
bool CanDrawPictures(const DemoState& state, std::string& error);
/// CanDrawPictures for a group of pictures (`what`, e.g. "haptics charts"): when they cannot be
/// drawn, a note when screenshots are off, else a missing-picture warning in the report naming why.
bool CanDrawPicturesOrWarn(DemoState& state, const std::string& stage, const std::string& what);
/// A 4-up picture (axial, 3D, sagittal, coronal) of the scene into the output folder, slices at
/// the point (or following the node's origin). False with `error` when it cannot be drawn here.
bool DemoScreenshot(DemoState& state, const double slicePointRAS[3], const std::string& followNodeID,
                    const std::string& file, std::string& error);
/// The bone models alone, each in its colour, from the front and from the lateral side, framed
/// on the bones, into the output folder. False with `error` when it cannot be drawn here.
bool DemoBoneViews(DemoState& state, const std::vector<std::string>& modelIDs, const std::string& file,
                   std::string& error);
/// An image slice (a CT re-sliced, one component) windowed to grey levels into the PNG `file` of the
/// output folder; needs no display. False with `error` when it cannot be written.
bool DemoSlicePicture(DemoState& state, vtkImageData* slice, double window, double level, const std::string& file,
                      std::string& error);

/// The stages in order.
std::vector<DemoStage> DemoStages();

}  // namespace rp
