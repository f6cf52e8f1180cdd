#include "rpBoneScores.h"

#include <cmath>
#include <map>
#include <memory>

#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>

#include "rpImageVolume.h"
#include "rpKneePhantom.h"
#include "rpLabelmapToMesh.h"
#include "rpMeshSignedDistance.h"
#include "vtkRPSegmentationNode.h"

namespace rp {
namespace {

// The value of `labels` at each voxel centre of the segmentation's grid (nearest voxel; 0
// outside), in the segmentation's voxel order.
std::vector<int> SampleOnSegmentationGrid(const ImageVolume& labels, vtkRPSegmentationNode* segmentation) {
  int dims[3], ldims[3];
  segmentation->GetImageData()->GetDimensions(dims);
  labels.Image->GetDimensions(ldims);
  vtkNew<vtkMatrix4x4> rasToLabels, segToLabels;
  vtkMatrix4x4::Invert(labels.IJKToRAS, rasToLabels);
  vtkMatrix4x4::Multiply4x4(rasToLabels, segmentation->GetIJKToRASMatrix(), segToLabels);
  std::vector<int> out(size_t(dims[0]) * dims[1] * dims[2], 0);
  size_t n = 0;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i, ++n) {
        double p[4] = {double(i), double(j), double(k), 1.0};
        segToLabels->MultiplyPoint(p, p);
        const int q[3] = {int(std::lround(p[0])), int(std::lround(p[1])), int(std::lround(p[2]))};
        if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= ldims[0] || q[1] >= ldims[1] || q[2] >= ldims[2]) continue;
        out[n] = int(labels.Image->GetScalarComponentAsDouble(q[0], q[1], q[2], 0));
      }
  return out;
}

}  // namespace

std::vector<TruthBone> PhantomTruthBones(const ImageVolume& labels, const KneeModel& model,
                                         vtkRPSegmentationNode* segmentation, std::string& error) {
  std::vector<TruthBone> bones;
  if (labels.Empty() || !segmentation || !segmentation->GetImageData()) {
    error = "no phantom labels or no segmentation to score";
    return bones;
  }
  const std::vector<int> values = SampleOnSegmentationGrid(labels, segmentation);
  for (const KneeBone& bone : KneeBones()) {
    TruthBone truth;
    truth.Name = bone.Name;
    truth.Mask.resize(values.size());
    for (size_t n = 0; n < values.size(); ++n) truth.Mask[n] = values[n] == bone.Cortical || values[n] == bone.Trabecular;
    const KneeStructure surface = bone.Surface;
    const KneeModel* m = &model;
    truth.Distance = [m, surface](const double p[3]) { return m->SignedDistance(surface, p); };
    truth.SurfacePoints = model.SurfacePoints(surface, 6000);
    bones.push_back(std::move(truth));
  }
  return bones;
}

std::vector<TruthBone> LabelmapTruthBones(const ImageVolume& labels, const std::vector<std::string>& names,
                                          vtkRPSegmentationNode* segmentation, std::string& error) {
  std::vector<TruthBone> bones;
  if (labels.Empty() || !segmentation || !segmentation->GetImageData()) {
    error = "no truth labelmap or no segmentation to score";
    return bones;
  }
  const std::vector<int> values = SampleOnSegmentationGrid(labels, segmentation);
  std::map<int, size_t> counts;
  for (int v : values)
    if (v != 0) ++counts[v];
  if (counts.empty()) {
    error = "the truth labelmap has no labelled voxel inside the CT";
    return bones;
  }
  int dims[3];
  segmentation->GetImageData()->GetDimensions(dims);
  for (const auto& [value, count] : counts) {
    TruthBone truth;
    truth.Name = value < int(names.size()) && !names[size_t(value)].empty() ? names[size_t(value)]
                                                                            : "label " + std::to_string(value);
    truth.Mask.resize(values.size());
    for (size_t n = 0; n < values.size(); ++n) truth.Mask[n] = values[n] == value;
    // The true surface: the label's own closed surface on the segmentation's grid.
    vtkNew<vtkImageData> mask;
    mask->SetDimensions(dims);
    mask->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
    std::copy(truth.Mask.begin(), truth.Mask.end(), static_cast<unsigned char*>(mask->GetScalarPointer()));
    vtkNew<vtkPolyData> surface;
    MeshStats stats;
    std::string meshError;
    if (LabelmapToMesh(mask, segmentation->GetIJKToRASMatrix(), 1, MeshOptions{}, surface, stats, meshError)) {
      auto distance = std::make_shared<MeshSignedDistance>();
      TriangleMesh triangles;
      for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i) {
        const double* p = surface->GetPoint(i);
        triangles.Points.push_back({p[0], p[1], p[2]});
        truth.SurfacePoints.push_back({p[0], p[1], p[2]});
      }
      vtkIdType npts;
      const vtkIdType* ids;
      for (surface->GetPolys()->InitTraversal(); surface->GetPolys()->GetNextCell(npts, ids);)
        if (npts == 3) triangles.Triangles.push_back({int32_t(ids[0]), int32_t(ids[1]), int32_t(ids[2])});
      if (distance->Build(triangles, meshError)) {
        truth.Distance = [distance](const double p[3]) { return distance->SignedDistance({p[0], p[1], p[2]}); };
      }
    }
    (void)count;
    bones.push_back(std::move(truth));
  }
  return bones;
}

std::vector<BoneScore> ScoreBones(const std::vector<TruthBone>& truth, vtkRPSegmentationNode* segmentation,
                                  const std::function<vtkPolyData*(const std::string&)>& meshOf,
                                  const double clipBounds[6]) {
  std::vector<BoneScore> scores;
  const auto* labels = static_cast<const unsigned char*>(segmentation->GetImageData()->GetScalarPointer());
  const vtkIdType n = segmentation->GetImageData()->GetNumberOfPoints();
  const bool wide = segmentation->GetImageData()->GetScalarType() != VTK_UNSIGNED_CHAR;
  auto labelAt = [&](vtkIdType i) {
    return wide ? int(segmentation->GetImageData()->GetPointData()->GetScalars()->GetTuple1(i)) : int(labels[i]);
  };
  std::map<int, size_t> segmentVoxels;
  for (vtkIdType i = 0; i < n; ++i) ++segmentVoxels[labelAt(i)];
  for (const TruthBone& bone : truth) {
    BoneScore score;
    score.Truth = bone.Name;
    // The segment overlapping the truth bone most.
    std::map<int, size_t> overlap;
    size_t truthVoxels = 0;
    for (vtkIdType i = 0; i < n; ++i) {
      if (!bone.Mask[size_t(i)]) continue;
      ++truthVoxels;
      const int l = labelAt(i);
      if (l != 0) ++overlap[l];
    }
    int best = 0;  // among the bone segments
    for (const auto& [label, count] : overlap) {
      const vtkRPSegmentationNode::Segment* candidate = segmentation->GetSegmentByLabel(label);
      if (!candidate || candidate->TissueClass != "bone") continue;
      if (!best || count > overlap[best]) best = label;
    }
    const vtkRPSegmentationNode::Segment* segment = best ? segmentation->GetSegmentByLabel(best) : nullptr;
    if (segment) {
      score.SegmentID = segment->ID;
      score.SegmentName = segment->Name;
      score.Dice = 2.0 * overlap[best] / double(truthVoxels + segmentVoxels[best]);
      vtkPolyData* mesh = meshOf(segment->ID);
      if (mesh && bone.Distance) {
        score.HasSurface = true;
        score.Surface = CompareToSurface(mesh, bone.Distance, bone.SurfacePoints, clipBounds);
      }
    }
    scores.push_back(std::move(score));
  }
  return scores;
}

}  // namespace rp
