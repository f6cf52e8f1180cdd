#pragma once
// A volume file that is a labelmap (ITK-SNAP, TotalSegmentator, nnU-Net, Slicer's "labelmap
// volume": plain integer NRRD/NIfTI) taken as a segmentation: one segment per label value, named
// and coloured from a label table when one is given, "Label N" otherwise. `roboplan mesh` and
// `roboplan convert <labelmap> <x.seg.nrrd>` take labelmaps this way.
//
// Labelmap or intensity image? `--input-kind labelmap|intensity` decides; `auto` takes a labelmap when
// no threshold option was given, the voxels are whole numbers >= 0 with few distinct values, and
// a label table was given, the file is named like one (*-label.*, *_label.*, *.label.*,
// *labelmap*, *.seg.*) or the caller has other evidence (convert: the output is a .seg.nrrd).
// The reason is returned so the caller can say it.
#include <string>
#include <vector>

#include "rpLabelTable.h"

class vtkImageData;
class vtkMatrix4x4;
class vtkRPSegmentationNode;

namespace rp {

enum class InputKind { Auto, Labelmap, Intensity };
bool ParseInputKind(const std::string& text, InputKind& kind);

/// Distinct voxel values of an image, up to a limit.
struct ImageValues {
  bool WholeNumbers = true;   // every value is an integer (also for float/double images)
  bool TooMany = false;       // more than the limit: Values is incomplete
  double Min = 0, Max = 0;
  std::vector<long> Values;   // sorted, 0 included when present
  std::vector<long> Counts;   // voxels per value
};
ImageValues CollectImageValues(vtkImageData* image, size_t limit);

/// At most this many labels (besides 0) make a labelmap.
constexpr size_t MaxLabels = 1000;

struct InputChoice {
  bool Labelmap = false;
  std::string Reason;  // e.g. "labelmap: 3 label values and a file name ending in -label"
  /// The image's values when the auto rule looked at them (then `Scanned`): passed on to
  /// LabelmapToSegmentation so a large labelmap is scanned once.
  bool Scanned = false;
  ImageValues Values;
};

InputChoice ChooseInputKind(InputKind requested, vtkImageData* image, const std::string& fileName,
                            bool haveLabelTable, bool intensityOptionsGiven);
/// The same rule with other evidence that the image is a labelmap in place of a label table, e.g.
/// "a .seg.nrrd output" (`roboplan convert`): "" when there is none.
InputChoice ChooseInputKind(InputKind requested, vtkImageData* image, const std::string& fileName,
                            const std::string& labelEvidence);

/// True when the file name says "labelmap" (see above).
bool LabelmapFileName(const std::string& fileName);

/// Fills `segmentation` (labelmap + one segment per non-zero value, its tissue class the table's
/// or, failing that, the one its name gives: KnownTissueClass) from `labels`. Integer images
/// are used as they are (not copied: pass a copy when the volume must stay independent);
/// float/double images of whole numbers are converted to the smallest integer type that holds
/// them. Fails, leaving `segmentation` untouched, on negative or fractional values, more than
/// MaxLabels labels or no label at all. `table` may be null. `known`: the values of `labels`
/// already collected (CollectImageValues with a limit of MaxLabels + 1), or null.
bool LabelmapToSegmentation(vtkImageData* labels, const vtkMatrix4x4* ijkToRAS, const LabelTable* table,
                            vtkRPSegmentationNode* segmentation, std::string& error,
                            const ImageValues* known = nullptr);

}  // namespace rp
