#ifndef vtkRPVolumesLogic_h
#define vtkRPVolumesLogic_h
// Volumes logic (no Qt): loads CT/MR volumes (DICOM, NRRD, NIfTI) into the scene as scalar
// volume nodes, adds the knee phantom, and registers a moving volume onto a fixed one by
// mutual information into a transform node that the moving volume then hangs under (so the
// MR is shown aligned with the CT). A failed load or registration leaves the scene unchanged.
#include <atomic>
#include <string>

#include <vtkObject.h>

#include "rpKneePhantom.h"
#include "rpProgress.h"
#include "rpVolumeFiles.h"
#include "rpVolumeRegistration.h"

class vtkRPScene;
class vtkRPScalarVolumeNode;
class vtkRPLinearTransformNode;
class vtkRPSegmentationNode;

class vtkRPVolumesLogic : public vtkObject {
 public:
  static vtkRPVolumesLogic* New();
  vtkTypeMacro(vtkRPVolumesLogic, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  void SetScene(vtkRPScene* scene) { this->Scene = scene; }
  vtkRPScene* GetScene() const { return this->Scene; }

  /// Reads `path` and adds a volume node named `name` (file name when empty). nullptr + error
  /// on failure; the scene is not touched then.
  vtkRPScalarVolumeNode* LoadVolume(const std::string& path, const std::string& name, std::string& error,
                                    const rp::VolumeReadOptions& options = {},
                                    const rp::ProgressCallback& progress = nullptr);
  /// Adds an in-memory volume as a node.
  vtkRPScalarVolumeNode* AddVolume(const rp::ImageVolume& volume, const std::string& name);

  /// Registers `moving` onto `fixed` and puts `moving` under a transform node named
  /// "<moving>To<fixed>" (to-parent = moving RAS → fixed RAS). When the optimizer did not
  /// converge nothing is changed and `error` says why. The result details go to `result`
  /// whenever the optimizer ran (its StopReason set), converged or not.
  vtkRPLinearTransformNode* RegisterVolumes(vtkRPScalarVolumeNode* fixed, vtkRPScalarVolumeNode* moving,
                                            const rp::RigidRegistrationOptions& options,
                                            rp::RigidRegistrationResult& result, std::string& error,
                                            const rp::ProgressCallback& progress = nullptr,
                                            const std::atomic<bool>* cancel = nullptr);

 protected:
  vtkRPVolumesLogic() = default;
  ~vtkRPVolumesLogic() override = default;

 private:
  vtkRPVolumesLogic(const vtkRPVolumesLogic&) = delete;
  void operator=(const vtkRPVolumesLogic&) = delete;
  vtkRPScene* Scene = nullptr;  // not owned (the host owns the scene)
};

#endif
