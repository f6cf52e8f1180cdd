#ifndef vtkRPVolumesLogic_h
#define vtkRPVolumesLogic_h
// Volumes logic (no Qt): loads CT/MR volumes (DICOM, NRRD, NIfTI) into the scene as scalar
// volume nodes, writes the knee phantom's files, registers a moving volume onto a fixed one by
// mutual information into a transform node that the moving volume then hangs under (so the
// MR is shown aligned with the CT), and scores a segmentation against a truth labelmap. A
// failed load or registration leaves the scene unchanged. `roboplan dicom`, `convert`, `phantom`,
// `register-volumes` and `compare-labels` run through it.
#include <atomic>
#include <map>
#include <string>
#include <vector>

#include <vtkObject.h>

#include "rpDicomSeries.h"
#include "rpKneePhantom.h"
#include "rpLabelComparison.h"
#include "rpProgress.h"
#include "rpSceneFormats.h"
#include "rpSegmentationConversion.h"
#include "rpVolumeFiles.h"
#include "rpVolumeRegistration.h"

class vtkRPScene;
class vtkRPScalarVolumeNode;
class vtkRPLinearTransformNode;
class vtkRPSegmentationNode;
class vtkRPNode;

class vtkRPVolumesLogic : public vtkObject {
 public:
  static vtkRPVolumesLogic* New();
  vtkTypeMacro(vtkRPVolumesLogic, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  void SetScene(vtkRPScene* scene) { this->Scene = scene; }
  vtkRPScene* GetScene() const { return this->Scene; }

  /// Reads `path` and adds a volume node named `name` (file name when empty). nullptr + error
  /// on failure; the scene is not touched then. `warnings` (when given) receives the read's.
  vtkRPScalarVolumeNode* LoadVolume(const std::string& path, const std::string& name, std::string& error,
                                    const rp::VolumeReadOptions& options = {},
                                    const rp::ProgressCallback& progress = nullptr,
                                    std::vector<std::string>* warnings = nullptr);
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

  /// A volume from one format to another: read with rp::ReadVolume (a DICOM series — `options`
  /// picks one of several — or a volume file; `warnings` receives the read's) and written with
  /// rp::WriteVolume (a volume file name → that format; anything else → a DICOM series folder of
  /// `modality`, "CT" or "MR", or when empty the input's if MR, else CT, described as the input).
  /// `converted` receives the volume read. False with `error` naming the file and the problem.
  bool ConvertVolume(const std::string& in, const std::string& out, const rp::VolumeReadOptions& options,
                     const std::string& modality, rp::ImageVolume& converted, std::vector<std::string>& warnings,
                     std::string& error, const rp::ProgressCallback& progress = nullptr);

  /// What a DICOM folder, DICOMDIR or file holds (rp::ScanDicom): its image stacks (each with
  /// the ID LoadVolume's options take, and why one cannot be read) and its SEGs and RTSTRUCTs.
  /// False with `error` when the path cannot be scanned; an empty result is not an error here.
  bool ScanDicomFolder(const std::string& path, rp::DicomScanResult& scan, std::string& error,
                       const rp::ProgressCallback& progress = nullptr);
  /// A scene file into another scene format (.rpscene, Slicer's .mrml and .mrb; rp::ConvertScene).
  rp::SceneConversion ConvertScene(const std::string& in, const std::string& out);
  /// A segmentation into a .seg.nrrd, or a .seg.nrrd into a DICOM SEG (rpSegmentationConversion.h);
  /// the result says whether the request is a segmentation conversion at all (Applies).
  rp::SegmentationConversion ConvertSegmentation(const rp::SegmentationConversionRequest& request);

  /// What WriteKneePhantom wrote: the phantom itself and where each part went.
  struct KneePhantomFiles {
    rp::KneePhantom Phantom;
    std::string CT, MR, Labels, TruthTransform;   // paths
    std::map<std::string, std::string> Surfaces;  // structure name → .vtp (real anatomy only)
  };
  /// Generates the knee phantom (rp::GenerateKneePhantom) and writes it into `folder` (created):
  /// the CT and the MR as DICOM series CT/ and MR/ (one patient; stale slices removed first) or
  /// ct.nrrd and mr.nrrd, the true labels (labels.nrrd, on the CT grid), the true surfaces
  /// (surfaces/<structure>.vtp, LPS) and the true MR-to-CT transform (MRToCT-truth.tfm, ITK LPS
  /// "from parent"). False with `error` naming what could not be made or written.
  bool WriteKneePhantom(const rp::KneePhantomOptions& options, const std::string& folder, bool dicom,
                        KneePhantomFiles& files, std::string& error, const rp::ProgressCallback& progress = nullptr);

  /// Reads a labelmap through the loader: a segmentation (.seg.nrrd, a DICOM SEG/RTSTRUCT) or a
  /// labelmap volume, added to the scene. nullptr + error (naming the path) for anything else; the
  /// scene is not touched then.
  vtkRPNode* LoadLabelmap(const std::string& path, std::string& error);
  /// A segmentation scored against a truth, segment by segment (rp::CompareLabels: Dice, surface
  /// distances; each label matched to the truth label it overlaps most). Both are segmentation or
  /// labelmap volume nodes; a segmentation's segments name its labels.
  struct LabelName {
    std::string ID, Name;
  };
  struct LabelScores {
    rp::LabelComparison Comparison;
    std::map<int, LabelName> Names, TruthNames;  // by label value (segmentations only)
  };
  bool CompareLabels(vtkRPNode* segmentation, vtkRPNode* truth, const std::vector<int>& labels, LabelScores& scores,
                     std::string& error);

 protected:
  vtkRPVolumesLogic() = default;
  ~vtkRPVolumesLogic() override = default;

 private:
  vtkRPVolumesLogic(const vtkRPVolumesLogic&) = delete;
  void operator=(const vtkRPVolumesLogic&) = delete;
  vtkRPScene* Scene = nullptr;  // not owned (the host owns the scene)
};

#endif
