#ifndef vtkRPDrillingLogic_h
#define vtkRPDrillingLogic_h
// The Drilling module's logic (what Module::Logic() returns; main thread only): builds the voxel
// bone from a segmentation node's segments (cortical/trabecular from a CT volume node when one is
// chosen), keeps it across sessions, shows it as a model node "<segment> (drilled)", and runs a
// drilling session with the simulated device (moved by the panel or the mouse) or following a
// tracked tool. Update() from a display-rate timer swaps the re-contoured mesh into that model
// node and moves the HapticInterfacePoint / HapticProxy tool nodes.
#include <memory>
#include <string>
#include <vector>

#include <vtkObject.h>

#include "rpDrillBoneBuilder.h"
#include "rpDrillServo.h"

class vtkRPScene;

namespace rp {
class DrillSession;
class SimulatedDevice;
}  // namespace rp

class vtkRPDrillingLogic : public vtkObject {
 public:
  static vtkRPDrillingLogic* New();
  vtkTypeMacro(vtkRPDrillingLogic, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  void SetScene(vtkRPScene* scene) { this->Scene = scene; }
  vtkRPScene* GetScene() const { return this->Scene; }

  struct BoneChoice {
    std::string SegmentationID;                  // a vtkRPSegmentationNode in the scene
    std::vector<std::string> BoneSegments;       // segment IDs to drill
    std::vector<std::string> ProtectedSegments;  // segment IDs the burr must not reach
    std::string CTVolumeID;                      // optional vtkRPScalarVolumeNode (HU → cortical/trabecular)
    double VoxelMm = 0.3;
  };
  /// Builds the voxel bone and its model node (stops a running session). False names the problem.
  bool BuildBone(const BoneChoice& choice, std::string& error);
  bool HasBone() const { return static_cast<bool>(this->Bone); }
  const rp::DrillBoneReport& GetBoneReport() const { return this->Report; }
  const std::string& GetDrilledModelID() const { return this->ModelID; }
  /// Drillable tissue names (index = DrillState material index).
  std::vector<std::string> GetTissueNames() const;

  /// Starts drilling with the simulated device (its pose from SetSimulatedBurrPosition or a
  /// tracked tool). False names the problem (no bone, already running, ...).
  bool StartSimulated(std::string& error);
  void Stop();
  bool IsRunning() const;
  void SetBurrOn(bool on);
  void SetBurrRadius(double mm);
  void SetRpm(double rpm);
  const rp::DrillControl& GetControl() const { return this->Control; }
  /// Undo the last stroke / restore the bone as built (while running; done by the servo thread).
  void Undo();
  void ResetBone();
  /// Moves the simulated burr to a RAS point (through HapticDeviceToRAS when the scene has one).
  void SetSimulatedBurrPosition(const double ras[3]);
  /// Follows this transformable node's origin (e.g. a tracked drill's tip) instead; "" stops.
  void SetFollowedNodeID(const std::string& id) { this->FollowedID = id; }
  /// The drill path recording written while running ("" none).
  void SetRecordPath(const std::string& path) { this->RecordPath = path; }
  const std::string& GetRecordPath() const { return this->RecordPath; }

  /// Display-rate update (main thread). True when the drilled model changed.
  bool Update();
  bool ReadState(rp::DrillState& state) const;
  rp::DrillSession* GetSession() const { return this->Session.get(); }
  /// A picture of the tunnel along the path drilled so far (or from → to when given).
  bool SaveTunnelPicture(const std::string& path, std::string& error);

 protected:
  vtkRPDrillingLogic();
  ~vtkRPDrillingLogic() override;

 private:
  vtkRPDrillingLogic(const vtkRPDrillingLogic&) = delete;
  void operator=(const vtkRPDrillingLogic&) = delete;

  vtkRPScene* Scene = nullptr;  // not owned
  std::unique_ptr<rp::DrillVolume> Bone;
  rp::TriangleMesh ProtectedSurface;
  std::vector<rp::Material> Materials;
  rp::DrillBoneReport Report;
  std::vector<std::string> BoneNames;  // segment names (their haptic models are left to the burr)
  std::string ModelID, FollowedID, RecordPath;
  rp::DrillControl Control;
  std::unique_ptr<rp::SimulatedDevice> Device;
  std::unique_ptr<rp::DrillSession> Session;
  std::vector<rp::Vec3> LastPath;  // the burr path of the last session (pictures after Stop)
};

#endif
