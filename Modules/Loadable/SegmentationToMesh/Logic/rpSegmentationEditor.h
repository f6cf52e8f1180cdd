#pragma once
// ITK segmentation on the labelmap of a vtkRPSegmentationNode: global threshold (with presets),
// connected-threshold region growing, confidence-connected growing, morphology and connected
// components. Every operation writes one segment (one label value, one tissue class); several
// tissues share the labelmap. On failure the labelmap and segment table are left as they were.
#include <array>
#include <string>
#include <vector>

class vtkRPImageNode;
class vtkRPSegmentationNode;

namespace rp {

struct ThresholdPreset {
  std::string Name;         // "bone", "cortical", "soft-tissue", "fat"
  std::string TissueClass;  // materials key
  double Lower, Upper;      // HU, inclusive
  std::array<double, 3> Color;
};

/// CT presets (HU): bone ≥ 226 (whole bone incl. trabecular), cortical ≥ 700,
/// soft tissue -100..225, fat -190..-30.
const std::vector<ThresholdPreset>& ThresholdPresets();
const ThresholdPreset* FindThresholdPreset(const std::string& name);

/// Which segment an operation writes, and how.
struct SegmentTarget {
  std::string ID;
  std::string Name;          // defaults to ID
  std::string TissueClass;
  std::array<double, 3> Color = {0.9, 0.85, 0.7};
  /// false: only unlabelled voxels (and the segment's own) are taken; other segments are kept.
  bool Overwrite = false;
  /// A result covering more than this fraction of the volume is refused as a leak.
  double MaxFraction = 0.9;
};

enum class Morphology { Closing, Opening, FillHoles, Dilate, Erode };
bool ParseMorphology(const std::string& text, Morphology& op);

struct EditResult {
  long Voxels = 0;          // voxels of the segment afterwards
  double Fraction = 0;      // of the whole volume
  long Components = 0;      // for component operations: components found
  std::vector<std::string> SegmentIDs;  // segments created (split)
};

class SegmentationEditor {
 public:
  /// An empty labelmap (unsigned char) on the volume's grid; segments removed.
  static bool InitializeFromVolume(vtkRPImageNode* volume, vtkRPSegmentationNode* segmentation, std::string& error);

  static bool Threshold(vtkRPImageNode* volume, vtkRPSegmentationNode* segmentation, const SegmentTarget& target,
                        double lower, double upper, EditResult& result, std::string& error);
  /// Connected threshold from seed points (RAS); every seed must lie inside [lower, upper].
  static bool RegionGrow(vtkRPImageNode* volume, vtkRPSegmentationNode* segmentation, const SegmentTarget& target,
                         const std::vector<std::array<double, 3>>& seedsRAS, double lower, double upper,
                         EditResult& result, std::string& error);
  /// Confidence connected: mean ± multiplier·σ of the seeds' neighbourhood, re-estimated per iteration.
  static bool ConfidenceConnected(vtkRPImageNode* volume, vtkRPSegmentationNode* segmentation,
                                  const SegmentTarget& target, const std::vector<std::array<double, 3>>& seedsRAS,
                                  double multiplier, int iterations, int radius, EditResult& result,
                                  std::string& error);
  /// Morphology with a ball of `radiusMm` (per-axis radius in voxels from the spacing, ≥ 1).
  static bool ApplyMorphology(vtkRPSegmentationNode* segmentation, const std::string& segmentID, Morphology op,
                              double radiusMm, EditResult& result, std::string& error);
  static bool KeepLargestComponent(vtkRPSegmentationNode* segmentation, const std::string& segmentID,
                                   EditResult& result, std::string& error);
  static bool KeepComponentAtSeed(vtkRPSegmentationNode* segmentation, const std::string& segmentID,
                                  const std::array<double, 3>& seedRAS, EditResult& result, std::string& error);
  /// Splits into one segment per component (largest first, up to `maxSegments`, components
  /// smaller than `minVoxels` are dropped). New IDs: <id>_1, <id>_2, ...; the first keeps <id>.
  static bool SplitComponents(vtkRPSegmentationNode* segmentation, const std::string& segmentID, int maxSegments,
                              long minVoxels, EditResult& result, std::string& error);
};

}  // namespace rp
