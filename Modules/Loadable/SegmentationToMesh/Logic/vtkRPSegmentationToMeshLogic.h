#ifndef vtkRPSegmentationToMeshLogic_h
#define vtkRPSegmentationToMeshLogic_h
// The SegmentationToMesh module's logic (what Module::Logic() returns; main thread only), the
// one way to segment and mesh whoever asks: the panel, `roboplan mesh` and the demo's
// segmentation stage call these functions.
//  - The input: a volume or a segmentation, opened by the one loader (rpDataLoader.h).
//  - A segmentation: from a labelmap volume (one segment per label value), the bones of a CT
//    one by one (rpBoneSplit.h), or tissues segmented on a volume (threshold, region growing,
//    confidence connected) and edited (morphology, components): SegmentTissue runs a method and
//    its edits as one recipe, EditSegment one edit.
//  - Models: one closed display + haptic surface per segment (rpSegmentationToModels.h), added
//    to the scene and replacing the models this logic made before for the same segment; a
//    preview of one segment's surface in a temporary model.
//  - A segmentation scored against a truth labelmap (Dice, surface distances).
#include <array>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <vtkObject.h>

#include "rpBoneSplit.h"
#include "rpDataLoader.h"
#include "rpLabelComparison.h"
#include "rpLabelmapInput.h"
#include "rpSegmentationEditor.h"
#include "rpSegmentationToModels.h"

class vtkRPNode;
class vtkRPScalarVolumeNode;
class vtkRPScene;
class vtkRPSegmentationNode;

namespace rp {

/// How a tissue is found on an intensity volume.
struct SegmentMethod {
  enum Kind { Threshold, RegionGrow, ConfidenceConnected };
  Kind Method = Threshold;
  double Lower = 226, Upper = 3071;                // HU: Threshold, RegionGrow
  std::vector<std::array<double, 3>> Seeds;       // RAS mm: RegionGrow, ConfidenceConnected
  double Multiplier = 2.5;                         // ConfidenceConnected: mean ± k·σ
  int Iterations = 3, Radius = 2;                  // ConfidenceConnected
  /// "threshold", "region-grow", "confidence" (the command's --method words).
  std::string Name() const;
};
bool ParseSegmentMethod(const std::string& text, SegmentMethod::Kind& kind);

/// One edit of a segment.
struct SegmentEdit {
  enum Kind { Closing, Opening, FillHoles, KeepLargest, KeepAtSeed, Split };
  Kind Edit = FillHoles;
  double RadiusMm = 0;                 // Closing, Opening
  std::array<double, 3> Seed{};        // KeepAtSeed (RAS mm)
  int MaxSegments = 1;                 // Split: up to this many segments, one per component
  /// "closing", "opening", "fill-holes", "keep-largest", "keep-at-seed", "split".
  std::string Name() const;
};

/// A tissue: the segment it writes, the method that finds it, then its edits in order.
struct TissueRecipe {
  SegmentTarget Target;
  SegmentMethod Method;
  std::vector<SegmentEdit> Edits;
};

/// What one step of a recipe did (the method's, then each edit's).
struct TissueStep {
  std::string Segment, Step;
  bool Ok = false;
  EditResult Result;
};

}  // namespace rp

class vtkRPSegmentationToMeshLogic : public vtkObject {
 public:
  static vtkRPSegmentationToMeshLogic* New();
  vtkTypeMacro(vtkRPSegmentationToMeshLogic, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  void SetScene(vtkRPScene* scene);
  vtkRPScene* GetScene() const { return this->Scene; }

  // ---- the input
  /// A volume or a segmentation from `path` (file, DICOM folder or DICOMDIR, DICOM SEG/RTSTRUCT)
  /// through the one loader, added to the scene. A plain labelmap named *.seg.nrrd (no Slicer
  /// segment keys) is read as a volume. nullptr with `error`; the loader's warnings are appended.
  vtkRPNode* LoadInput(const std::string& path, const rp::ReadOptions& options, std::vector<std::string>& warnings,
                       std::string& error);

  // ---- segmentations (each new node is added to the scene)
  /// An empty segmentation node.
  vtkRPSegmentationNode* AddSegmentation(const std::string& name);
  /// A labelmap volume as a new segmentation named `name`: one segment per label value, named
  /// and coloured from `table` (may be null), else "Label N". `copyVoxels`: the segmentation gets
  /// a copy (the volume stays as loaded while the segmentation is edited); false: they share the
  /// voxels (a caller that is done with the volume saves the copy). `known`: the volume's values
  /// when already collected (rp::InputChoice). nullptr with `error`; the scene is not touched.
  vtkRPSegmentationNode* SegmentationFromLabelmap(vtkRPScalarVolumeNode* volume, const rp::LabelTable* table,
                                                  const std::string& name, bool copyVoxels, std::string& error,
                                                  const rp::ImageValues* known = nullptr);
  /// The bones of a CT one by one as a new segmentation named `name` (rp::SplitBones). nullptr
  /// with `error`; the scene is not touched.
  vtkRPSegmentationNode* SplitBones(vtkRPScalarVolumeNode* ct, const rp::BoneSplitOptions& options,
                                    const std::string& name, rp::BoneSplitResult& result, std::string& error,
                                    const rp::ProgressCallback& progress = nullptr);
  /// One tissue on `volume` into `segmentation`: the recipe's method, then its edits in order.
  /// Every step run is appended to `steps` (a failing one too, with Ok false); stops at the
  /// first that fails (false, `error` names why).
  bool SegmentTissue(vtkRPScalarVolumeNode* volume, vtkRPSegmentationNode* segmentation,
                     const rp::TissueRecipe& recipe, std::vector<rp::TissueStep>& steps, std::string& error);
  /// One edit of one segment. False with `error`; the segmentation is then as it was.
  bool EditSegment(vtkRPSegmentationNode* segmentation, const std::string& segmentID, const rp::SegmentEdit& edit,
                   rp::EditResult& result, std::string& error);

  // ---- models
  /// The display (+ haptic) models of the segments `options` names (all when none), added to
  /// the scene in one batch; the models this logic made before for a segment that meshed are
  /// removed (a segment that fails keeps them). `built` as rp::BuildSegmentModels' `done`.
  std::vector<rp::SegmentModels> CreateModels(vtkRPSegmentationNode* segmentation,
                                              const rp::ModelBuildOptions& options,
                                              const rp::ProgressCallback& progress = nullptr,
                                              const std::function<void(const rp::SegmentModels&)>& built = nullptr);
  /// One segment's display surface in a temporary model "<segment> (preview)", not haptic,
  /// replaced by the next preview and removed with the next CreateModels that meshes a segment.
  bool PreviewSegment(vtkRPSegmentationNode* segmentation, const std::string& segmentID,
                      const rp::ModelBuildOptions& options, rp::MeshStats& stats, std::string& error,
                      const rp::ProgressCallback& progress = nullptr);
  void RemovePreview();
  /// The preview model's node ID ("" when none, also when it was removed from the scene).
  std::string GetPreviewNodeID() const;

  // ---- scoring
  /// Each segment of `segmentation` against the labelmap file `truthPath` (Dice, surface
  /// distances between boundary voxels). False with `error`.
  bool CompareWithTruth(vtkRPSegmentationNode* segmentation, const std::string& truthPath,
                        rp::LabelComparison& comparison, std::string& error);

 protected:
  vtkRPSegmentationToMeshLogic();
  ~vtkRPSegmentationToMeshLogic() override;

 private:
  vtkRPSegmentationToMeshLogic(const vtkRPSegmentationToMeshLogic&) = delete;
  void operator=(const vtkRPSegmentationToMeshLogic&) = delete;
  bool RunMethod(vtkRPScalarVolumeNode* volume, vtkRPSegmentationNode* segmentation, const rp::SegmentTarget& target,
                 const rp::SegmentMethod& method, rp::EditResult& result, std::string& error);

  vtkRPScene* Scene = nullptr;  // not owned (the host owns the scene)
  std::string PreviewID;
  /// Models this logic created, per segmentation node ID and segment ID (replaced by the next
  /// CreateModels of that segment).
  std::map<std::string, std::map<std::string, std::vector<std::string>>> CreatedModelIDs;
};

#endif
