#include "rpLabelmapInput.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <type_traits>
#include <unordered_map>

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSMPThreadLocal.h>

#include "rpDicomSegmentation.h"
#include "rpParallelFor.h"
#include "vtkRPSegmentationNode.h"

namespace rp {

bool ParseInputKind(const std::string& text, InputKind& kind) {
  if (text == "auto") kind = InputKind::Auto;
  else if (text == "labelmap" || text == "label") kind = InputKind::Labelmap;
  else if (text == "intensity" || text == "volume") kind = InputKind::Intensity;
  else return false;
  return true;
}

namespace {

// 8- and 16-bit images: a histogram over the type's whole range. A labelmap is long runs of one
// value: 16 bytes of voxels equal to their first (two 8-byte compares) are counted with one
// increment, 4x faster on a 512x512x300 labelmap. Other blocks go to four interleaved histograms:
// one would make every increment wait for the previous one to the same bin (a store-to-load chain).
template <typename T>
void SmallTypeValues(const T* v, vtkIdType n, ImageValues& out) {
  constexpr long offset = -static_cast<long>(std::numeric_limits<T>::lowest());
  constexpr size_t bins = static_cast<size_t>(std::numeric_limits<T>::max()) + offset + 1;
  constexpr int lanes = 4;
  vtkSMPThreadLocal<std::vector<long>> local(std::vector<long>(lanes * bins, 0));
  ParallelFor(0, n, [&](vtkIdType b, vtkIdType e) {
    long* h = local.Local().data();
    auto bin = [&](vtkIdType i) { return static_cast<size_t>(static_cast<long>(v[i]) + offset); };
    constexpr int block = static_cast<int>(16 / sizeof(T));
    vtkIdType i = b;
    for (; i + block <= e; i += block) {
      T repeated[block / 2];
      std::fill(repeated, repeated + block / 2, v[i]);
      uint64_t pattern, first, second;
      std::memcpy(&pattern, repeated, 8);
      std::memcpy(&first, v + i, 8);
      std::memcpy(&second, v + i + block / 2, 8);
      if (first == pattern && second == pattern) {
        h[bin(i)] += block;
        continue;
      }
      for (int k = 0; k < block; k += lanes) {
        ++h[bin(i + k)];
        ++h[bins + bin(i + k + 1)];
        ++h[2 * bins + bin(i + k + 2)];
        ++h[3 * bins + bin(i + k + 3)];
      }
    }
    for (; i < e; ++i) ++h[bin(i)];
  });
  std::vector<long> histogram(bins, 0);
  for (const auto& h : local)
    for (size_t lane = 0; lane < lanes; ++lane)
      for (size_t i = 0; i < bins; ++i) histogram[i] += h[lane * bins + i];
  for (size_t i = 0; i < bins; ++i) {
    if (!histogram[i]) continue;
    out.Values.push_back(static_cast<long>(i) - offset);
    out.Counts.push_back(histogram[i]);
  }
}

// A thread's values of an image of another type (outside GeneralValues: vtkSMPThreadLocal of a
// type local to a function templated on the voxel type compiles its SMP back-ends once per type).
struct ValuesLocal {
  std::unordered_map<long, long> Counts;
  bool TooMany = false, Fractional = false;
  double Min = std::numeric_limits<double>::max(), Max = std::numeric_limits<double>::lowest();
};

// Other types: a map per thread, abandoned past the limit (the range is still scanned).
template <typename T>
void GeneralValues(const T* v, vtkIdType n, size_t limit, ImageValues& out) {
  using Local = ValuesLocal;
  vtkSMPThreadLocal<Local> locals;
  ParallelFor(0, n, [&](vtkIdType b, vtkIdType e) {
    Local& l = locals.Local();
    for (vtkIdType i = b; i < e; ++i) {
      const double x = static_cast<double>(v[i]);
      l.Min = std::min(l.Min, x), l.Max = std::max(l.Max, x);
      if (l.TooMany || l.Fractional) continue;
      if constexpr (std::is_floating_point_v<T>) {
        if (!std::isfinite(x) || x != std::floor(x) || std::abs(x) > 2e9) {
          l.Fractional = true;
          continue;
        }
      }
      ++l.Counts[static_cast<long>(x)];
      if (l.Counts.size() > limit) l.TooMany = true;
    }
  });
  std::map<long, long> merged;
  out.Min = std::numeric_limits<double>::max(), out.Max = std::numeric_limits<double>::lowest();
  for (const Local& l : locals) {
    out.Min = std::min(out.Min, l.Min), out.Max = std::max(out.Max, l.Max);
    out.TooMany = out.TooMany || l.TooMany;
    out.WholeNumbers = out.WholeNumbers && !l.Fractional;
    for (const auto& [value, count] : l.Counts) merged[value] += count;
  }
  if (merged.size() > limit) out.TooMany = true;
  for (const auto& [value, count] : merged) {
    out.Values.push_back(value);
    out.Counts.push_back(count);
  }
}

template <typename T>
void CollectValues(const T* v, vtkIdType n, size_t limit, ImageValues& out) {
  if constexpr (std::is_integral_v<T> && sizeof(T) <= 2) {
    SmallTypeValues(v, n, out);
    if (!out.Values.empty()) out.Min = static_cast<double>(out.Values.front()), out.Max = static_cast<double>(out.Values.back());
    out.TooMany = out.Values.size() > limit;
  } else {
    GeneralValues(v, n, limit, out);
  }
}

std::string Plural(size_t n, const std::string& word) {
  return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

template <typename T>
void ConvertLabels(vtkImageData* from, T* to) {
  vtkDataArray* scalars = from->GetPointData()->GetScalars();
  ParallelFor(0, from->GetNumberOfPoints(), [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType i = b; i < e; ++i) to[i] = static_cast<T>(scalars->GetComponent(i, 0));
  });
}

}  // namespace

ImageValues CollectImageValues(vtkImageData* image, size_t limit) {
  ImageValues values;
  if (!image || !image->GetPointData()->GetScalars() || image->GetNumberOfScalarComponents() != 1) {
    values.WholeNumbers = false;
    return values;
  }
  switch (image->GetScalarType()) {
    vtkTemplateMacro(CollectValues(static_cast<const VTK_TT*>(image->GetScalarPointer()), image->GetNumberOfPoints(),
                                   limit, values));
    default:
      values.WholeNumbers = false;
  }
  return values;
}

bool LabelmapFileName(const std::string& fileName) {
  std::string name = std::filesystem::path(fileName).filename().string();
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const char* key : {"-label.", "_label.", ".label.", "labelmap", ".seg."})
    if (name.find(key) != std::string::npos) return true;
  return false;
}

InputChoice ChooseInputKind(InputKind requested, vtkImageData* image, const std::string& fileName,
                            bool haveLabelTable, bool intensityOptionsGiven) {
  if (intensityOptionsGiven && requested == InputKind::Auto) {
    InputChoice choice;
    choice.Reason = "intensity image (threshold or segmentation options given)";
    return choice;
  }
  return ChooseInputKind(requested, image, fileName, haveLabelTable ? "a label table" : "");
}

InputChoice ChooseInputKind(InputKind requested, vtkImageData* image, const std::string& fileName,
                            const std::string& labelEvidence) {
  InputChoice choice;
  auto decide = [&](bool labelmap, const std::string& reason) {
    choice.Labelmap = labelmap;
    choice.Reason = reason;
    return choice;
  };
  if (requested == InputKind::Labelmap) return decide(true, "labelmap (--input-kind labelmap)");
  if (requested == InputKind::Intensity) return decide(false, "intensity image (--input-kind intensity)");
  choice.Scanned = true;
  choice.Values = CollectImageValues(image, MaxLabels + 1);
  const ImageValues& values = choice.Values;
  if (!values.WholeNumbers) return decide(false, "intensity image (fractional voxel values)");
  if (values.TooMany) return decide(false, "intensity image (more than " + std::to_string(MaxLabels) + " distinct values)");
  if (values.Min < 0) return decide(false, "intensity image (negative values)");
  if (values.Values.empty()) return decide(false, "intensity image (no voxels)");
  const size_t labels = values.Values.size() - (values.Values.front() == 0 ? 1 : 0);
  const std::string what = Plural(labels, "label value");
  if (LabelmapFileName(fileName)) return decide(true, "labelmap (" + what + ", the file name says labelmap)");
  if (!labelEvidence.empty()) return decide(true, "labelmap (" + what + " and " + labelEvidence + ")");
  return decide(false, "intensity image (whole numbers with " + what +
                     ": if it is a labelmap, say --input-kind labelmap or give --labels)");
}

bool LabelmapToSegmentation(vtkImageData* labels, const vtkMatrix4x4* ijkToRAS, const LabelTable* table,
                            vtkRPSegmentationNode* segmentation, std::string& error, const ImageValues* known) {
  if (!labels || !labels->GetPointData()->GetScalars() || labels->GetNumberOfPoints() == 0 || !segmentation) {
    error = "the labelmap has no voxels";
    return false;
  }
  if (labels->GetNumberOfScalarComponents() != 1) {
    error = "a labelmap has one value per voxel (this image has " +
            std::to_string(labels->GetNumberOfScalarComponents()) + " components)";
    return false;
  }
  const ImageValues values = known ? *known : CollectImageValues(labels, MaxLabels + 1);
  if (!values.WholeNumbers) {
    error = "not a labelmap: the voxels hold fractional values (use --input-kind intensity and thresholds)";
    return false;
  }
  if (values.TooMany) {
    error = "not a labelmap: more than " + std::to_string(MaxLabels) + " distinct values (use --input-kind intensity)";
    return false;
  }
  if (values.Min < 0) {
    error = "not a labelmap: negative value " + std::to_string(static_cast<long>(values.Min)) +
            " (labels are >= 0, 0 = background)";
    return false;
  }
  std::vector<long> present;
  for (long v : values.Values)
    if (v != 0) present.push_back(v);
  if (present.empty()) {
    error = "the labelmap is empty (every voxel is 0)";
    return false;
  }
  vtkSmartPointer<vtkImageData> image = labels;
  const int type = labels->GetScalarType();
  if (type == VTK_FLOAT || type == VTK_DOUBLE) {
    image = vtkSmartPointer<vtkImageData>::New();
    image->SetDimensions(labels->GetDimensions());
    const double top = values.Max;
    const int integerType = top <= 255 ? VTK_UNSIGNED_CHAR : top <= 65535 ? VTK_UNSIGNED_SHORT : VTK_INT;
    image->AllocateScalars(integerType, 1);
    switch (integerType) {
      vtkTemplateMacro(ConvertLabels(labels, static_cast<VTK_TT*>(image->GetScalarPointer())));
    }
  } else if (values.Max > std::numeric_limits<int>::max()) {
    error = "not a labelmap: label value " + std::to_string(static_cast<long>(values.Max)) + " is too large";
    return false;
  }
  const int previous = segmentation->StartModify();
  segmentation->RemoveAllSegments();
  segmentation->SetImageData(image);
  segmentation->SetIJKToRASMatrix(ijkToRAS);
  for (long v : present) {
    vtkRPSegmentationNode::Segment s;
    s.LabelValue = static_cast<int>(v);
    const LabelEntry* entry = table ? table->Find(v) : nullptr;
    s.Name = entry && !entry->Name.empty() ? entry->Name : "Label " + std::to_string(v);
    s.ID = s.Name;
    if (segmentation->GetSegmentByID(s.ID)) s.ID += "_" + std::to_string(v);  // names need not be unique
    const auto color = entry ? entry->Color : DefaultLabelColor(v);
    for (int c = 0; c < 3; ++c) s.Color[c] = color[static_cast<size_t>(c)];
    s.TissueClass = entry && !entry->TissueClass.empty() ? entry->TissueClass : KnownTissueClass(s.Name);
    segmentation->SetSegment(s);
  }
  segmentation->Modified();
  segmentation->EndModify(previous);
  return true;
}

}  // namespace rp
