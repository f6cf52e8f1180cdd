#pragma once
// What the plan's figures know about the patient's tissue at a point (plain C++, no VTK): the CT
// number (trilinear), which segment of the segmentation holds it, and whether it is bone. With a
// segmentation, bone is every voxel of a segment whose tissue class is a bone of materials.json
// (a drillable tissue: "bone", "trabecular bone"); without one, bone is where the CT is at or above
// the bone threshold of materials.json (the lowest ctMinHU). The HU ranges of those tissues
// (cortical: "bone" from 600 HU, cancellous: "trabecular bone" 100-600 HU) classify bone by density.
#include <string>
#include <vector>

#include "rpVolumeSampler.h"

namespace rp {

/// A bone tissue's CT range, from materials.json: [MinHU, MaxHU).
struct BoneHURange {
  std::string Tissue;  // e.g. "bone" (cortical), "trabecular bone" (cancellous)
  double MinHU = 0, MaxHU = 0;
};

/// A segment of the segmentation, by label value.
struct LabelledTissue {
  int Label = 0;
  std::string Name;         // the segment's name, e.g. "Tibia"
  std::string TissueClass;  // e.g. "bone"
  bool IsBone = false;
};

class TissueModel {
 public:
  /// Either or both may be empty (then only what the other gives is known).
  VolumeSampler CT;
  VolumeSampler Labels;
  std::vector<LabelledTissue> Segments;
  /// Highest range first; the first one is cortical bone.
  std::vector<BoneHURange> BoneRanges;
  double BoneThresholdHU = 100;

  /// Builds the label lookup; call after filling Segments.
  void Prepare();
  bool HasCT() const { return !this->CT.Empty(); }
  bool HasLabels() const { return !this->Labels.Empty(); }
  /// 0..1, bone at or above 0.5: the trilinear mix of the 8 surrounding voxels' bone flags.
  double BoneIndicator(const Vec3& p) const noexcept;
  bool InBone(const Vec3& p) const noexcept { return this->BoneIndicator(p) >= 0.5; }
  /// CT number (0 without a CT).
  double HU(const Vec3& p) const noexcept { return this->HasCT() ? this->CT.Trilinear(p) : 0.0; }
  /// Index into TissueNames() of what is at p: a segment (with labels) or a bone HU range (without);
  /// the last name ("outside bone" / "no segment") for the rest.
  int TissueIndex(const Vec3& p) const noexcept;
  const std::vector<std::string>& TissueNames() const { return this->Names; }
  /// Index into BoneRanges of a CT number, -1 below every range.
  int BoneRangeOf(double hu) const noexcept;
  /// Sampling step along a tool: a quarter of the smallest voxel, at most 0.25 mm.
  double StepMm() const noexcept;
  /// The bone's extent of the world box (the box of the voxel centres of the CT, else the labels).
  bool Contains(const Vec3& p) const noexcept;

 private:
  std::vector<unsigned char> BoneByLabel;  // label value -> bone flag
  std::vector<int> TissueByLabel;          // label value -> index into Names
  std::vector<std::string> Names;
};

}  // namespace rp
