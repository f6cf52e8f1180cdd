// libRoboPlanSegmentationItk.so: the ITK side of rp::SegmentationEditor's edits
// (rpSegmentationEditor.h) and of the bone masks' morphology and distance map (rpBoneMasks.h),
// loaded by their forwarders in RoboPlanSegmentationToMeshLogic on the first such call
// (rpSegmentationItkEntries.h). Every ITK filter the module runs lives in this file.
#include "rpSegmentationItkEntries.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <type_traits>

#include <itkBinaryBallStructuringElement.h>
#include <itkBinaryDilateImageFilter.h>
#include <itkBinaryErodeImageFilter.h>
#include <itkBinaryFillholeImageFilter.h>
#include <itkBinaryMorphologicalClosingImageFilter.h>
#include <itkBinaryMorphologicalOpeningImageFilter.h>
#include <itkBinaryThresholdImageFilter.h>
#include <itkConfidenceConnectedImageFilter.h>
#include <itkConnectedComponentImageFilter.h>
#include <itkConnectedThresholdImageFilter.h>
#include <itkImage.h>
#include <itkRelabelComponentImageFilter.h>
#include <itkSignedMaurerDistanceMapImageFilter.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>

#include "rpParallelFor.h"
#include "vtkRPImageNode.h"
#include "vtkRPSegmentationNode.h"

namespace rp {

namespace {

using MaskImage = itk::Image<unsigned char, 3>;

// A binary mask over a box of the labelmap (start + size in voxels).
struct MaskBox {
  int Start[3] = {0, 0, 0};
  int Size[3] = {0, 0, 0};
  size_t Count() const { return static_cast<size_t>(Size[0]) * Size[1] * Size[2]; }
};

template <typename T>
typename itk::Image<T, 3>::Pointer Wrap(T* buffer, const int size[3]) {
  auto image = itk::Image<T, 3>::New();
  typename itk::Image<T, 3>::RegionType region;
  for (unsigned a = 0; a < 3; ++a) region.SetSize(a, static_cast<itk::SizeValueType>(size[a]));
  image->SetRegions(region);
  image->GetPixelContainer()->SetImportPointer(buffer, static_cast<size_t>(size[0]) * size[1] * size[2], false);
  return image;
}

void Dimensions(vtkImageData* image, int dims[3]) { image->GetDimensions(dims); }

bool SameGrid(vtkRPImageNode* a, vtkRPImageNode* b) {
  int da[3], db[3];
  Dimensions(a->GetImageData(), da);
  Dimensions(b->GetImageData(), db);
  if (da[0] != db[0] || da[1] != db[1] || da[2] != db[2]) return false;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      if (std::abs(a->GetIJKToRASMatrix()->GetElement(r, c) - b->GetIJKToRASMatrix()->GetElement(r, c)) > 1e-6) return false;
  return true;
}

// The segmentation must share the volume's grid; an empty segmentation is set up on it.
bool PrepareSegmentation(vtkRPImageNode* volume, vtkRPSegmentationNode* segmentation, std::string& error) {
  if (!segmentationitk::HasImage(volume)) {
    error = "the volume has no image data";
    return false;
  }
  if (volume->GetImageData()->GetNumberOfScalarComponents() != 1) {
    error = "the volume must have one scalar component";
    return false;
  }
  if (!segmentation) {
    error = "no segmentation given";
    return false;
  }
  if (!segmentationitk::HasImage(segmentation)) return SegmentationEditor::InitializeFromVolume(volume, segmentation, error);
  if (!SameGrid(volume, segmentation)) {
    error = "the segmentation's labelmap is not on the volume's grid (dimensions or IJK-to-RAS differ)";
    return false;
  }
  return true;
}

bool SeedToIndex(vtkRPImageNode* node, const std::array<double, 3>& ras, MaskImage::IndexType& index,
                 std::string& error) {
  vtkNew<vtkMatrix4x4> rasToIJK;
  node->GetRASToIJKMatrix(rasToIJK);
  const double p[4] = {ras[0], ras[1], ras[2], 1.0};
  double ijk[4];
  rasToIJK->MultiplyPoint(p, ijk);
  int dims[3];
  Dimensions(node->GetImageData(), dims);
  for (unsigned a = 0; a < 3; ++a) {
    const long i = std::lround(ijk[a]);
    if (i < 0 || i >= dims[a]) {
      error = "seed (" + std::to_string(ras[0]) + ", " + std::to_string(ras[1]) + ", " + std::to_string(ras[2]) +
              ") RAS is outside the volume";
      return false;
    }
    index[a] = i;
  }
  return true;
}

template <typename T>
T ClampTo(double v) {
  return static_cast<T>(std::clamp(v, static_cast<double>(std::numeric_limits<T>::lowest()),
                                   static_cast<double>(std::numeric_limits<T>::max())));
}

// A threshold range in the image's own voxel type. On integer images fractional bounds round
// inward ([0.9, 1.1] selects 1, not 0 and 1); a range holding no whole number is refused.
template <typename T>
bool VoxelRange(double lower, double upper, T& lo, T& hi, std::string& error) {
  if constexpr (std::is_integral_v<T>) {
    const double l = std::ceil(lower), u = std::floor(upper);
    if (l > u) {
      error = "threshold range [" + std::to_string(lower) + ", " + std::to_string(upper) +
              "] holds no whole number, and the image's voxels are integers";
      return false;
    }
    lo = ClampTo<T>(l), hi = ClampTo<T>(u);
  } else {
    lo = ClampTo<T>(lower), hi = ClampTo<T>(upper);
  }
  return true;
}

double LabelMax(vtkImageData* labelmap) { return labelmap->GetScalarTypeMax(); }

// Writes a mask over `box` into the segment `target`: the segment's old voxels are replaced.
// Returns the segment's voxel count afterwards. One pass over the box (parallel over slices),
// plus clearing the label outside the box when the box is not the whole image.
template <typename L>
long WriteLabels(L* labels, const int dims[3], const MaskBox& box, const unsigned char* mask, L label, bool overwrite) {
  const bool whole = box.Start[0] == 0 && box.Start[1] == 0 && box.Start[2] == 0 && box.Size[0] == dims[0] &&
                     box.Size[1] == dims[1] && box.Size[2] == dims[2];
  if (!whole) {
    ParallelFor(0, dims[2], [&](vtkIdType k0, vtkIdType k1) {
      for (vtkIdType k = k0; k < k1; ++k)
        for (int j = 0; j < dims[1]; ++j) {
          L* row = labels + (static_cast<size_t>(k) * dims[1] + j) * dims[0];
          const bool rowInBox = k >= box.Start[2] && k < box.Start[2] + box.Size[2] && j >= box.Start[1] &&
                                j < box.Start[1] + box.Size[1];
          for (int i = 0; i < dims[0]; ++i) {
            if (row[i] != label) continue;
            if (rowInBox && i >= box.Start[0] && i < box.Start[0] + box.Size[0]) continue;  // the box pass decides
            row[i] = 0;
          }
        }
    });
  }
  std::atomic<long> count{0};
  ParallelFor(0, box.Size[2], [&](vtkIdType k0, vtkIdType k1) {
    long local = 0;
    for (vtkIdType k = k0; k < k1; ++k)
      for (int j = 0; j < box.Size[1]; ++j) {
        const unsigned char* m = mask + (static_cast<size_t>(k) * box.Size[1] + j) * box.Size[0];
        L* row = labels + (static_cast<size_t>(box.Start[2] + k) * dims[1] + box.Start[1] + j) * dims[0] + box.Start[0];
        for (int i = 0; i < box.Size[0]; ++i) {
          if (m[i]) {
            if (row[i] == 0 || row[i] == label || overwrite) row[i] = label;
          } else if (row[i] == label) {
            row[i] = 0;
          }
          local += row[i] == label;
        }
      }
    count += local;
  });
  return count;
}

bool WriteSegment(vtkRPSegmentationNode* segmentation, const SegmentTarget& target, const MaskBox& box,
                  const unsigned char* mask, EditResult& result, std::string& error) {
  if (target.ID.empty()) {
    error = "the segment needs an ID";
    return false;
  }
  vtkImageData* labelmap = segmentation->GetImageData();
  int dims[3];
  Dimensions(labelmap, dims);
  const size_t total = static_cast<size_t>(dims[0]) * dims[1] * dims[2];
  std::atomic<long> selectedCount{0};
  ParallelFor(0, static_cast<vtkIdType>(box.Count()), [&](vtkIdType n0, vtkIdType n1) {
    long local = 0;
    for (vtkIdType n = n0; n < n1; ++n) local += mask[n] != 0;
    selectedCount += local;
  });
  const long selected = selectedCount;
  const double fraction = static_cast<double>(selected) / static_cast<double>(total);
  if (fraction > target.MaxFraction) {
    error = "segment '" + target.ID + "' would cover " + std::to_string(static_cast<int>(std::round(100 * fraction))) +
            " % of the volume (more than " + std::to_string(static_cast<int>(std::round(100 * target.MaxFraction))) +
            " %): the threshold or region growing leaked into everything; tighten the range or the seeds";
    return false;
  }
  const auto* existing = segmentation->GetSegmentByID(target.ID);
  const int label = existing ? existing->LabelValue : segmentation->GetUnusedLabelValue();
  if (label > LabelMax(labelmap)) {
    error = "label value " + std::to_string(label) + " does not fit the labelmap's voxel type";
    return false;
  }
  switch (labelmap->GetScalarType()) {
    vtkTemplateMacro(result.Voxels = WriteLabels(static_cast<VTK_TT*>(labelmap->GetScalarPointer()), dims, box, mask,
                                                 static_cast<VTK_TT>(label), target.Overwrite));
  }
  vtkRPSegmentationNode::Segment s;
  if (existing) s = *existing;
  s.ID = target.ID;
  s.Name = target.Name.empty() ? (existing ? existing->Name : target.ID) : target.Name;
  s.LabelValue = label;
  if (!target.TissueClass.empty() || !existing) s.TissueClass = target.TissueClass;
  if (!existing || !target.Name.empty()) {
    for (int c = 0; c < 3; ++c) s.Color[c] = target.Color[static_cast<size_t>(c)];
  }
  result.Fraction = static_cast<double>(result.Voxels) / static_cast<double>(total);
  labelmap->Modified();
  const int previous = segmentation->StartModify();
  segmentation->SetSegment(s);
  segmentation->Modified();
  segmentation->EndModify(previous);
  return true;
}

MaskBox WholeBox(vtkImageData* image) {
  MaskBox box;
  Dimensions(image, box.Size);
  return box;
}

// Mask of an existing segment over its bounding box padded by `pad` voxels (clamped).
template <typename L>
void ExtractSegment(const L* labels, const int dims[3], L label, int pad, MaskBox& box, std::vector<unsigned char>& mask) {
  int lo[3] = {dims[0], dims[1], dims[2]}, hi[3] = {-1, -1, -1};
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j) {
      const L* row = labels + (static_cast<size_t>(k) * dims[1] + j) * dims[0];
      for (int i = 0; i < dims[0]; ++i) {
        if (row[i] != label) continue;
        lo[0] = std::min(lo[0], i), hi[0] = std::max(hi[0], i);
        lo[1] = std::min(lo[1], j), hi[1] = std::max(hi[1], j);
        lo[2] = std::min(lo[2], k), hi[2] = std::max(hi[2], k);
      }
    }
  if (hi[0] < 0) {
    box = MaskBox();
    mask.clear();
    return;
  }
  for (int a = 0; a < 3; ++a) {
    box.Start[a] = std::max(0, lo[a] - pad);
    box.Size[a] = std::min(dims[a] - 1, hi[a] + pad) - box.Start[a] + 1;
  }
  mask.assign(box.Count(), 0);
  for (int k = 0; k < box.Size[2]; ++k)
    for (int j = 0; j < box.Size[1]; ++j) {
      const L* row = labels + (static_cast<size_t>(box.Start[2] + k) * dims[1] + box.Start[1] + j) * dims[0] + box.Start[0];
      unsigned char* m = mask.data() + (static_cast<size_t>(k) * box.Size[1] + j) * box.Size[0];
      for (int i = 0; i < box.Size[0]; ++i) m[i] = row[i] == label ? 1 : 0;
    }
}

bool SegmentMask(vtkRPSegmentationNode* segmentation, const std::string& segmentID, int pad, SegmentTarget& target,
                 MaskBox& box, std::vector<unsigned char>& mask, std::string& error) {
  if (!segmentation || !segmentationitk::HasImage(segmentation)) {
    error = "the segmentation has no labelmap";
    return false;
  }
  const auto* segment = segmentation->GetSegmentByID(segmentID);
  if (!segment) {
    error = "no segment '" + segmentID + "' in the segmentation";
    return false;
  }
  target.ID = segment->ID;
  target.MaxFraction = 1.0;
  target.Overwrite = false;
  vtkImageData* labelmap = segmentation->GetImageData();
  int dims[3];
  Dimensions(labelmap, dims);
  switch (labelmap->GetScalarType()) {
    vtkTemplateMacro(ExtractSegment(static_cast<const VTK_TT*>(labelmap->GetScalarPointer()), dims,
                                    static_cast<VTK_TT>(segment->LabelValue), pad, box, mask));
  }
  if (mask.empty()) {
    error = "segment '" + segmentID + "' is empty";
    return false;
  }
  return true;
}

// Runs `op(image)` on the volume as an ITK image of its own pixel type (no copy) for the common
// CT/MR types; others go through a float copy.
template <typename Op>
bool WithVolume(vtkRPImageNode* volume, Op&& op, std::string& error) {
  vtkImageData* image = volume->GetImageData();
  int dims[3];
  Dimensions(image, dims);
  try {
    switch (image->GetScalarType()) {
      case VTK_SHORT: return op(Wrap(static_cast<short*>(image->GetScalarPointer()), dims));
      case VTK_UNSIGNED_SHORT: return op(Wrap(static_cast<unsigned short*>(image->GetScalarPointer()), dims));
      case VTK_UNSIGNED_CHAR: return op(Wrap(static_cast<unsigned char*>(image->GetScalarPointer()), dims));
      case VTK_FLOAT: return op(Wrap(static_cast<float*>(image->GetScalarPointer()), dims));
      default: {
        std::vector<float> copy(static_cast<size_t>(image->GetNumberOfPoints()));
        vtkDataArray* scalars = image->GetPointData()->GetScalars();
        for (vtkIdType n = 0; n < image->GetNumberOfPoints(); ++n)
          copy[static_cast<size_t>(n)] = static_cast<float>(scalars->GetComponent(n, 0));
        return op(Wrap(copy.data(), dims));
      }
    }
  } catch (const itk::ExceptionObject& e) {
    error = std::string("ITK: ") + e.GetDescription();
  } catch (const std::exception& e) {
    error = e.what();
  }
  return false;
}

// Runs `makeMask(image)` (an ITK filter's mask, nullptr when it cannot run: `error` says why) on
// the volume in its own pixel type and writes the mask into the target segment: how every edit
// that reads the volume ends.
template <typename MakeMask>
bool WriteMaskOf(vtkRPImageNode* volume, vtkRPSegmentationNode* segmentation, const SegmentTarget& target,
                 EditResult& result, std::string& error, MakeMask&& makeMask) {
  return WithVolume(
      volume,
      [&](auto image) {
        const MaskImage::Pointer mask = makeMask(image);
        return mask && WriteSegment(segmentation, target, WholeBox(volume->GetImageData()), mask->GetBufferPointer(),
                                    result, error);
      },
      error);
}

// The seeds' voxels (each must lie in the volume).
bool SeedsToIndices(vtkRPImageNode* volume, const std::vector<std::array<double, 3>>& seedsRAS,
                    std::vector<MaskImage::IndexType>& seeds, std::string& error) {
  for (const auto& s : seedsRAS) {
    MaskImage::IndexType index;
    if (!SeedToIndex(volume, s, index, error)) return false;
    seeds.push_back(index);
  }
  return true;
}

bool ValidRange(double lower, double upper, std::string& error) {
  if (!(lower <= upper) || !std::isfinite(lower) || !std::isfinite(upper)) {
    error = "threshold range [" + std::to_string(lower) + ", " + std::to_string(upper) + "] is empty or not finite";
    return false;
  }
  return true;
}

}  // namespace

// The entries are the operations themselves: extern "C" names (no namespace in the symbol),
// defined inside namespace rp so that they read the helpers above as the editor's methods did.
RP_SEGMENTATION_ITK_ENTRY bool roboplan_segmentation_threshold(
    vtkRPImageNode* volume, vtkRPSegmentationNode* segmentation, const SegmentTarget& target,
    double lower, double upper, EditResult& result, std::string& error) {
  if (!ValidRange(lower, upper, error) || !PrepareSegmentation(volume, segmentation, error))
    return false;
  return WriteMaskOf(volume, segmentation, target, result, error,
                     [&](auto image) -> MaskImage::Pointer {
                       using ImageType = typename decltype(image)::ObjectType;
                       typename ImageType::PixelType lo, hi;
                       if (!VoxelRange(lower, upper, lo, hi, error)) return nullptr;
                       auto filter = itk::BinaryThresholdImageFilter<ImageType, MaskImage>::New();
                       filter->SetInput(image);
                       filter->SetLowerThreshold(lo);
                       filter->SetUpperThreshold(hi);
                       filter->SetInsideValue(1);
                       filter->SetOutsideValue(0);
                       filter->Update();
                       return filter->GetOutput();
                     });
}

RP_SEGMENTATION_ITK_ENTRY bool roboplan_segmentation_region_grow(
    vtkRPImageNode* volume, vtkRPSegmentationNode* segmentation, const SegmentTarget& target,
    const std::vector<std::array<double, 3>>& seedsRAS, double lower, double upper,
    EditResult& result, std::string& error) {
  if (!ValidRange(lower, upper, error) || !PrepareSegmentation(volume, segmentation, error))
    return false;
  if (seedsRAS.empty()) {
    error = "region growing needs at least one seed point";
    return false;
  }
  std::vector<MaskImage::IndexType> seeds;
  if (!SeedsToIndices(volume, seedsRAS, seeds, error)) return false;
  for (size_t n = 0; n < seeds.size(); ++n) {
    const auto& index = seeds[n];
    const double value = volume->GetImageData()->GetScalarComponentAsDouble(
        static_cast<int>(index[0]), static_cast<int>(index[1]), static_cast<int>(index[2]), 0);
    if (value < lower || value > upper) {
      const auto& s = seedsRAS[n];
      error = "seed (" + std::to_string(s[0]) + ", " + std::to_string(s[1]) + ", " + std::to_string(s[2]) +
              ") has value " + std::to_string(value) + ", outside the range [" + std::to_string(lower) + ", " +
              std::to_string(upper) + "]";
      return false;
    }
  }
  return WriteMaskOf(volume, segmentation, target, result, error, [&](auto image) -> MaskImage::Pointer {
    using ImageType = typename decltype(image)::ObjectType;
    typename ImageType::PixelType lo, hi;
    if (!VoxelRange(lower, upper, lo, hi, error)) return nullptr;
    auto filter = itk::ConnectedThresholdImageFilter<ImageType, MaskImage>::New();
    filter->SetInput(image);
    filter->SetLower(lo);
    filter->SetUpper(hi);
    filter->SetReplaceValue(1);
    for (const auto& s : seeds) filter->AddSeed(s);
    filter->Update();
    return filter->GetOutput();
  });
}

RP_SEGMENTATION_ITK_ENTRY bool roboplan_segmentation_confidence_connected(
    vtkRPImageNode* volume, vtkRPSegmentationNode* segmentation, const SegmentTarget& target,
    const std::vector<std::array<double, 3>>& seedsRAS, double multiplier, int iterations,
    int radius, EditResult& result, std::string& error) {
  if (!PrepareSegmentation(volume, segmentation, error)) return false;
  if (seedsRAS.empty()) {
    error = "confidence-connected growing needs at least one seed point";
    return false;
  }
  if (multiplier <= 0 || iterations < 0 || radius < 1) {
    error = "confidence connected needs multiplier > 0, iterations >= 0 and radius >= 1";
    return false;
  }
  std::vector<MaskImage::IndexType> seeds;
  if (!SeedsToIndices(volume, seedsRAS, seeds, error)) return false;
  return WriteMaskOf(volume, segmentation, target, result, error, [&](auto image) -> MaskImage::Pointer {
    using ImageType = typename decltype(image)::ObjectType;
    auto filter = itk::ConfidenceConnectedImageFilter<ImageType, MaskImage>::New();
    filter->SetInput(image);
    filter->SetMultiplier(multiplier);
    filter->SetNumberOfIterations(static_cast<unsigned>(iterations));
    filter->SetInitialNeighborhoodRadius(static_cast<unsigned>(radius));
    filter->SetReplaceValue(1);
    for (const auto& s : seeds) filter->AddSeed(s);
    filter->Update();
    return filter->GetOutput();
  });
}

namespace {
// `op` on a 0/1 mask with a ball of `radius` voxels per axis (each >= 1: ITK's ball is undefined
// for a zero semi-axis); a closing keeps a safe border, so the mask's box does not erode it.
MaskImage::Pointer MorphologyOf(MaskImage::Pointer input, Morphology op, const MaskImage::SizeType& radius) {
  using Ball = itk::BinaryBallStructuringElement<unsigned char, 3>;
  Ball ball;
  ball.SetRadius(radius);
  ball.CreateStructuringElement();
  switch (op) {
    case Morphology::Closing: {
      auto f = itk::BinaryMorphologicalClosingImageFilter<MaskImage, MaskImage, Ball>::New();
      f->SetInput(input), f->SetKernel(ball), f->SetForegroundValue(1), f->SafeBorderOn(), f->Update();
      return f->GetOutput();
    }
    case Morphology::Opening: {
      auto f = itk::BinaryMorphologicalOpeningImageFilter<MaskImage, MaskImage, Ball>::New();
      f->SetInput(input), f->SetKernel(ball), f->SetForegroundValue(1), f->SetBackgroundValue(0), f->Update();
      return f->GetOutput();
    }
    case Morphology::Dilate: {
      auto f = itk::BinaryDilateImageFilter<MaskImage, MaskImage, Ball>::New();
      f->SetInput(input), f->SetKernel(ball), f->SetForegroundValue(1), f->Update();
      return f->GetOutput();
    }
    case Morphology::Erode: {
      auto f = itk::BinaryErodeImageFilter<MaskImage, MaskImage, Ball>::New();
      f->SetInput(input), f->SetKernel(ball), f->SetForegroundValue(1), f->SetBackgroundValue(0), f->Update();
      return f->GetOutput();
    }
    case Morphology::FillHoles: {
      auto f = itk::BinaryFillholeImageFilter<MaskImage>::New();
      f->SetInput(input), f->SetForegroundValue(1), f->FullyConnectedOff(), f->Update();
      return f->GetOutput();
    }
  }
  return nullptr;
}
}  // namespace

RP_SEGMENTATION_ITK_ENTRY bool roboplan_segmentation_apply_morphology(
    vtkRPSegmentationNode* segmentation, const std::string& segmentID, Morphology op,
    double radiusMm, EditResult& result, std::string& error) {
  if (!segmentation || !segmentationitk::HasImage(segmentation)) {
    error = "the segmentation has no labelmap";
    return false;
  }
  double spacing[3];
  segmentation->GetSpacing(spacing);
  MaskImage::SizeType radius;
  int maxRadius = 0;
  for (unsigned a = 0; a < 3; ++a) {
    radius[a] = static_cast<itk::SizeValueType>(std::max(1L, std::lround(radiusMm / spacing[a])));
    maxRadius = std::max(maxRadius, static_cast<int>(radius[a]));
  }
  if (op != Morphology::FillHoles && !(radiusMm > 0)) {
    error = "morphology radius must be > 0 mm";
    return false;
  }
  SegmentTarget target;
  MaskBox box;
  std::vector<unsigned char> mask;
  if (!SegmentMask(segmentation, segmentID, maxRadius + 1, target, box, mask, error)) return false;
  try {
    const MaskImage::Pointer output = MorphologyOf(Wrap(mask.data(), box.Size), op, radius);
    return WriteSegment(segmentation, target, box, output->GetBufferPointer(), result, error);
  } catch (const itk::ExceptionObject& e) {
    error = std::string("ITK: ") + e.GetDescription();
  }
  return false;
}

namespace {
using ComponentImage = itk::Image<unsigned int, 3>;

// Components of a mask, relabelled by size (1 = largest).
ComponentImage::Pointer Components(MaskImage::Pointer mask, std::vector<itk::SizeValueType>& sizes) {
  auto cc = itk::ConnectedComponentImageFilter<MaskImage, ComponentImage>::New();
  cc->SetInput(mask);
  cc->FullyConnectedOff();
  auto relabel = itk::RelabelComponentImageFilter<ComponentImage, ComponentImage>::New();
  relabel->SetInput(cc->GetOutput());
  relabel->SortByObjectSizeOn();
  relabel->Update();
  sizes = relabel->GetSizeOfObjectsInPixels();
  return relabel->GetOutput();
}

bool KeepComponent(vtkRPSegmentationNode* segmentation, const std::string& segmentID,
                   const std::array<double, 3>* seedRAS, EditResult& result, std::string& error) {
  SegmentTarget target;
  MaskBox box;
  std::vector<unsigned char> mask;
  if (!SegmentMask(segmentation, segmentID, 0, target, box, mask, error)) return false;
  try {
    std::vector<itk::SizeValueType> sizes;
    ComponentImage::Pointer components = Components(Wrap(mask.data(), box.Size), sizes);
    unsigned int keep = 1;
    if (seedRAS) {
      MaskImage::IndexType index;
      if (!SeedToIndex(segmentation, *seedRAS, index, error)) return false;
      for (unsigned a = 0; a < 3; ++a) index[a] -= box.Start[a];
      bool inside = true;
      for (unsigned a = 0; a < 3; ++a) inside = inside && index[a] >= 0 && index[a] < box.Size[a];
      keep = inside ? components->GetPixel(index) : 0;
      if (keep == 0) {
        error = "the seed is not inside segment '" + segmentID + "'";
        return false;
      }
    }
    const unsigned int* c = components->GetBufferPointer();
    for (size_t n = 0; n < mask.size(); ++n) mask[n] = c[n] == keep ? 1 : 0;
    result.Components = static_cast<long>(sizes.size());
    return WriteSegment(segmentation, target, box, mask.data(), result, error);
  } catch (const itk::ExceptionObject& e) {
    error = std::string("ITK: ") + e.GetDescription();
  }
  return false;
}
}  // namespace

RP_SEGMENTATION_ITK_ENTRY bool roboplan_segmentation_keep_largest_component(
    vtkRPSegmentationNode* segmentation, const std::string& segmentID, EditResult& result,
    std::string& error) {
  return KeepComponent(segmentation, segmentID, nullptr, result, error);
}

RP_SEGMENTATION_ITK_ENTRY bool roboplan_segmentation_keep_component_at_seed(
    vtkRPSegmentationNode* segmentation, const std::string& segmentID,
    const std::array<double, 3>& seedRAS, EditResult& result, std::string& error) {
  return KeepComponent(segmentation, segmentID, &seedRAS, result, error);
}

RP_SEGMENTATION_ITK_ENTRY bool roboplan_segmentation_split_components(
    vtkRPSegmentationNode* segmentation, const std::string& segmentID, int maxSegments,
    long minVoxels, EditResult& result, std::string& error) {
  SegmentTarget target;
  MaskBox box;
  std::vector<unsigned char> mask;
  if (maxSegments < 1) {
    error = "split needs at least one segment";
    return false;
  }
  if (!SegmentMask(segmentation, segmentID, 0, target, box, mask, error)) return false;
  const auto original = *segmentation->GetSegmentByID(segmentID);
  try {
    std::vector<itk::SizeValueType> sizes;
    ComponentImage::Pointer components = Components(Wrap(mask.data(), box.Size), sizes);
    const unsigned int* c = components->GetBufferPointer();
    result.Components = static_cast<long>(sizes.size());
    int kept = 0;
    for (size_t k = 0; k < sizes.size() && kept < maxSegments; ++k) {
      if (static_cast<long>(sizes[k]) < minVoxels) break;
      ++kept;
    }
    if (kept == 0) {
      error = "segment '" + segmentID + "' has no component of at least " + std::to_string(minVoxels) + " voxels";
      return false;
    }
    // The segment keeps the largest component; the others become new segments.
    for (int k = kept; k >= 1; --k) {
      std::vector<unsigned char> part(mask.size());
      for (size_t n = 0; n < mask.size(); ++n) part[n] = c[n] == static_cast<unsigned int>(k) ? 1 : 0;
      SegmentTarget t;
      t.ID = k == 1 ? original.ID : original.ID + "_" + std::to_string(k);
      t.Name = k == 1 ? original.Name : original.Name + " " + std::to_string(k);
      t.TissueClass = original.TissueClass;
      t.Color = {original.Color[0], original.Color[1], original.Color[2]};
      t.MaxFraction = 1.0;
      t.Overwrite = true;
      // Rewriting the original segment last also clears the components that were dropped.
      EditResult partResult;
      if (!WriteSegment(segmentation, t, box, part.data(), partResult, error)) return false;
      result.SegmentIDs.insert(result.SegmentIDs.begin(), t.ID);
      if (k == 1) result.Voxels = partResult.Voxels, result.Fraction = partResult.Fraction;
    }
    return true;
  } catch (const itk::ExceptionObject& e) {
    error = std::string("ITK: ") + e.GetDescription();
  }
  return false;
}

RP_SEGMENTATION_ITK_ENTRY bool roboplan_bone_mask_morphology(std::vector<uint8_t>& mask,
                                                             const bonesplit::Box& box,
                                                             Morphology op, const int radius[3],
                                                             std::string& error) {
  MaskImage::SizeType ball;
  for (unsigned a = 0; a < 3; ++a)
    ball[a] = static_cast<itk::SizeValueType>(std::max(1, radius[a]));
  try {
    const MaskImage::Pointer output = MorphologyOf(Wrap(mask.data(), box.Size), op, ball);
    std::copy_n(output->GetBufferPointer(), mask.size(), mask.data());
    return true;
  } catch (const itk::ExceptionObject& e) {
    error = std::string("bone mask morphology: ") + e.GetDescription();
  }
  return false;
}

RP_SEGMENTATION_ITK_ENTRY bool roboplan_bone_distance_inside(std::vector<uint8_t>& mask,
                                                             const bonesplit::Box& box,
                                                             const double spacing[3],
                                                             std::vector<float>& distance,
                                                             std::string& error) {
  distance.assign(mask.size(), 0.0f);
  MaskImage::Pointer itkMask = Wrap(mask.data(), box.Size);
  const double itkSpacing[3] = {spacing[0], spacing[1], spacing[2]};
  itkMask->SetSpacing(itkSpacing);
  auto map = itk::SignedMaurerDistanceMapImageFilter<MaskImage, itk::Image<float, 3>>::New();
  map->SetInput(itkMask);
  map->SetInsideIsPositive(true);
  map->SetUseImageSpacing(true);
  map->SetSquaredDistance(false);
  map->SetBackgroundValue(0);
  try {
    map->Update();
  } catch (const itk::ExceptionObject& e) {
    error = std::string("distance map: ") + e.GetDescription();
    return false;
  }
  const float* d = map->GetOutput()->GetBufferPointer();
  for (size_t i = 0; i < mask.size(); ++i) distance[i] = mask[i] ? std::max(0.0f, d[i]) : 0.0f;
  return true;
}

}  // namespace rp

// Each entry's type is the C++ function's (a compile error here when one side changes).
namespace rp::segmentationitk {
static_assert(std::is_same_v<decltype(&roboplan_segmentation_threshold), ThresholdFunction>);
static_assert(std::is_same_v<decltype(&roboplan_segmentation_region_grow), RegionGrowFunction>);
static_assert(std::is_same_v<decltype(&roboplan_segmentation_confidence_connected), ConfidenceConnectedFunction>);
static_assert(std::is_same_v<decltype(&roboplan_segmentation_apply_morphology), ApplyMorphologyFunction>);
static_assert(std::is_same_v<decltype(&roboplan_segmentation_keep_largest_component), KeepLargestComponentFunction>);
static_assert(std::is_same_v<decltype(&roboplan_segmentation_keep_component_at_seed), KeepComponentAtSeedFunction>);
static_assert(std::is_same_v<decltype(&roboplan_segmentation_split_components), SplitComponentsFunction>);
static_assert(std::is_same_v<decltype(&roboplan_bone_mask_morphology), MaskMorphologyFunction>);
static_assert(std::is_same_v<decltype(&roboplan_bone_distance_inside), DistanceInsideBoneFunction>);
}  // namespace rp::segmentationitk
