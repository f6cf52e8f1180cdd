#include "rpSegmentationIO.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <vector>

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>

#include "rpDataLoader.h"
#include "rpItkImageIOEntries.h"
#include "rpLPSRAS.h"
#include "rpMemoryBudget.h"
#include "rpNodeStorage.h"
#include "rpStorageFormats.h"
#include "rpSegmentationHeader.h"
#include "rpVolumeIO.h"
#include "vtkRPSegmentationNode.h"

// Slicer's .seg.nrrd: a labelmap NRRD (3-D single layer, or 4-D "list domain domain domain"
// with one layer per list entry) plus key/value fields per segment. Slicer's reader
// (vtkMRMLSegmentationStorageNode) keys segments by their index N in "Segment<N>_*".
namespace rp {
namespace {

std::string FormatDouble(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.6g", v);
  return buffer;
}

// The conversion parameters of Slicer 5.0.3's own four rules (vtkSegmentationCore's
// *ConversionRule.cxx: names, defaults, descriptions), name|value|description joined by '&', so
// Slicer offers the same surface options when it loads our files. A name no rule of the reading
// Slicer defines is an error there (SlicerRT's planar-contour 'Default slice thickness' and 'End
// capping' logged two per file in stock Slicer).
const char* const DefaultConversionParameters =
    "Collapse labelmaps|1|Merge the labelmaps into as few shared labelmaps as possible 1 = created labelmaps will "
    "be shared if possible without overwriting each other.&Compute surface normals|1|Compute surface normals. 1 "
    "(default) = surface normals are computed. 0 = surface normals are not computed (slightly faster but produces "
    "less smooth surface display).&Crop to reference image geometry|0|Crop the model to the extent of reference "
    "geometry. 0 (default) = created labelmap will contain the entire model. 1 = created labelmap extent will be "
    "within reference image extent.&Decimation factor|0.0|Desired reduction in the total number of polygons. "
    "Range: 0.0 (no decimation) to 1.0 (as much simplification as possible). Value of 0.8 typically reduces data "
    "set size by 80% without losing too much details.&Fractional labelmap oversampling factor|1|Determines the "
    "oversampling of the reference image geometry.&Joint smoothing|0|Perform joint smoothing.&Oversampling factor|1|Determines the oversampling of "
    "the reference image geometry.&Smoothing factor|0.5|Smoothing factor. Range: 0.0 (no smoothing) to 1.0 "
    "(strong smoothing).&Threshold fraction|0.5|Determines the threshold that the closed surface is created at "
    "as a fractional value between 0 and 1.";

template <typename T>
void ComputeExtents(const T* voxels, const int dims[3], std::map<long, std::array<int, 6>>& extents) {
  for (int k = 0; k < dims[2]; ++k) {
    for (int j = 0; j < dims[1]; ++j) {
      const T* row = voxels + (static_cast<size_t>(k) * dims[1] + j) * dims[0];
      for (int i = 0; i < dims[0]; ++i) {
        if (row[i] == 0) continue;
        auto it = extents.find(static_cast<long>(row[i]));
        if (it == extents.end()) {
          extents[static_cast<long>(row[i])] = {i, i, j, j, k, k};
          continue;
        }
        auto& e = it->second;
        e[0] = std::min(e[0], i), e[1] = std::max(e[1], i);
        e[2] = std::min(e[2], j), e[3] = std::max(e[3], j);
        e[4] = std::min(e[4], k), e[5] = std::max(e[5], k);
      }
    }
  }
}

// The extent written for every segment: all segments are in layer 0, and every segment of a layer
// gets the layer's extent (the union of its segments' voxels), as Slicer writes it. Slicer 5.0.3
// crops the shared layer to the extent of the first segment it reads in it, so a tight extent per
// segment would empty the others. Our reader reads the whole layer either way.
std::string LayerExtent(vtkRPSegmentationNode* node, const std::map<long, std::array<int, 6>>& extents) {
  std::array<int, 6> layer = {0, -1, 0, -1, 0, -1};  // Slicer's empty extent
  bool empty = true;
  for (int n = 0; n < node->GetNumberOfSegments(); ++n) {
    auto it = extents.find(node->GetNthSegment(n).LabelValue);
    if (it == extents.end()) continue;
    const auto& e = it->second;
    for (int a = 0; a < 6; a += 2) {
      layer[a] = empty ? e[a] : std::min(layer[a], e[a]);
      layer[a + 1] = empty ? e[a + 1] : std::max(layer[a + 1], e[a + 1]);
    }
    empty = false;
  }
  return std::to_string(layer[0]) + " " + std::to_string(layer[1]) + " " + std::to_string(layer[2]) + " " +
         std::to_string(layer[3]) + " " + std::to_string(layer[4]) + " " + std::to_string(layer[5]);
}

}  // namespace

bool WriteSegmentationFile(const std::string& path, vtkRPSegmentationNode* node, std::string& error) {
  if (!node) {
    error = "cannot write '" + path + "': no segmentation given";
    return false;
  }
  vtkImageData* image = node->GetImageData();
  if (!image || !image->GetPointData()->GetScalars() || image->GetNumberOfPoints() == 0) {
    error = "cannot write '" + path + "': segmentation '" + node->GetName() +
            "' has no labelmap";
    return false;
  }
  if (!vtkRPSegmentationNode::IsLabelScalarType(image->GetScalarType()) || image->GetNumberOfScalarComponents() != 1) {
    error = "cannot write '" + path + "': the labelmap must hold one integer label per voxel";
    return false;
  }
  int dims[3];
  image->GetDimensions(dims);
  std::map<long, std::array<int, 6>> extents;
  switch (image->GetScalarType()) {
    vtkTemplateMacro(ComputeExtents(static_cast<const VTK_TT*>(image->GetScalarPointer()), dims, extents));
  }
  const std::string layerExtent = LayerExtent(node, extents);
  std::map<std::string, std::string> metadata;
  std::set<int> labels;
  for (int n = 0; n < node->GetNumberOfSegments(); ++n) {
    const auto& s = node->GetNthSegment(n);
    if (!labels.insert(s.LabelValue).second) {
      error = "cannot write '" + path + "': two segments share label value " + std::to_string(s.LabelValue);
      return false;
    }
    const std::string prefix = "Segment" + std::to_string(n) + "_";
    metadata[prefix + "ID"] = s.ID;
    metadata[prefix + "Name"] = s.Name;
    metadata[prefix + "NameAutoGenerated"] = "0";
    metadata[prefix + "Color"] = FormatDouble(s.Color[0]) + " " + FormatDouble(s.Color[1]) + " " + FormatDouble(s.Color[2]);
    metadata[prefix + "ColorAutoGenerated"] = "0";
    metadata[prefix + "LabelValue"] = std::to_string(s.LabelValue);
    metadata[prefix + "Layer"] = "0";
    metadata[prefix + "Extent"] = layerExtent;
    std::string tags = "Segmentation.Status:inprogress|";
    if (!s.TissueClass.empty()) tags += std::string(SegmentTissueTag) + ":" + s.TissueClass + "|";
    std::map<std::string, std::string> protection;
    WriteProtection(s.Protection, protection, ProtectedSegmentTag, SafetyMarginSegmentTag);
    for (const auto& [key, value] : protection) tags += key + ":" + value + "|";
    metadata[prefix + "Tags"] = tags;
  }
  metadata["Segmentation_MasterRepresentation"] = "Binary labelmap";
  metadata["Segmentation_ContainedRepresentationNames"] = "Binary labelmap|";
  metadata["Segmentation_ConversionParameters"] = DefaultConversionParameters;
  metadata["Segmentation_ReferenceImageExtentOffset"] = "0 0 0";
  return WriteVolumeFile(path, image, node->GetIJKToRASMatrix(), metadata, error);
}

bool ReadSegmentationFile(const std::string& path, vtkRPSegmentationNode* node, std::string& error) {
  if (!node) {
    error = "cannot read '" + path + "': no segmentation node given";
    return false;
  }
  // Read everything into temporaries first: the node stays as it was on failure.
  auto image = vtkSmartPointer<vtkImageData>::New();
  vtkNew<vtkMatrix4x4> ijkToRAS;
  VolumeFileData data;
  data.Image = image;
  data.IJKToRAS = ijkToRAS;
  std::vector<vtkSmartPointer<vtkImageData>> layers;
  std::map<std::string, std::string> metadata;
  std::string volumeError;
  if (ReadVolumeFile(path, data, volumeError)) {
    layers.push_back(image);
    metadata = data.Metadata;
  } else if (volumeError.find("components per voxel") != std::string::npos ||
             volumeError.find("4-D") != std::string::npos) {
    const auto readLayers = itkimageio::Entry<itkimageio::ReadLayersFunction>(itkimageio::ReadLayersEntry, path, error);
    if (!readLayers || !readLayers(path, layers, ijkToRAS, metadata, error)) return false;
  } else {
    error = volumeError;
    return false;
  }
  for (const auto& layer : layers) {
    if (!vtkRPSegmentationNode::IsLabelScalarType(layer->GetScalarType())) {
      error = "'" + path + "': a segmentation labelmap must have integer voxels, not " +
              std::string(layer->GetScalarTypeAsString());
      return false;
    }
  }
  std::vector<SegmentationHeaderSegment> segments;
  if (!ParseSegmentationHeader(path, metadata, segments, error)) return false;
  if (segments.empty() && metadata.find("Segmentation_MasterRepresentation") == metadata.end() &&
      metadata.find("Segmentation_SourceRepresentation") == metadata.end()) {
    error = "'" + path + "': no Segment<N>_ID keys: not a Slicer segmentation file";
    return false;
  }
  for (const auto& fs : segments) {
    if (fs.Layer >= static_cast<int>(layers.size())) {
      error = "'" + path + "': segment '" + fs.Segment.ID + "' is on layer " + std::to_string(fs.Layer) + " but the file has " +
              std::to_string(layers.size()) + " layer(s)";
      return false;
    }
  }

  vtkSmartPointer<vtkImageData> labelmap = layers.front();
  std::vector<vtkRPSegmentationNode::Segment> result;
  if (layers.size() == 1) {
    for (const auto& fs : segments) result.push_back(fs.Segment);
  } else {
    // Several layers: merge into one labelmap with a fresh label per segment. Where segments of
    // different layers overlap, the later layer wins (our node holds one label per voxel).
    const int type = segments.size() < 256 ? VTK_UNSIGNED_CHAR : VTK_UNSIGNED_SHORT;
    labelmap = vtkSmartPointer<vtkImageData>::New();
    labelmap->SetDimensions(layers.front()->GetDimensions());
    labelmap->AllocateScalars(type, 1);
    vtkDataArray* target = labelmap->GetPointData()->GetScalars();
    target->Fill(0);
    const vtkIdType count = labelmap->GetNumberOfPoints();
    int nextLabel = 1;
    for (size_t l = 0; l < layers.size(); ++l) {
      std::map<long, int> remap;
      for (const auto& fs : segments) {
        if (fs.Layer != static_cast<int>(l)) continue;
        auto s = fs.Segment;
        remap[s.LabelValue] = nextLabel;
        s.LabelValue = nextLabel++;
        result.push_back(s);
      }
      vtkDataArray* source = layers[l]->GetPointData()->GetScalars();
      for (vtkIdType n = 0; n < count; ++n) {
        const long value = static_cast<long>(source->GetComponent(n, 0));
        if (value == 0) continue;
        auto it = remap.find(value);
        if (it != remap.end()) target->SetComponent(n, 0, it->second);
      }
    }
  }
  const int previous = node->StartModify();
  node->SetImageData(labelmap);
  node->SetIJKToRASMatrix(ijkToRAS);
  node->RemoveAllSegments();
  for (const auto& s : result) node->SetSegment(s);
  node->EndModify(previous);
  return true;
}

namespace {
class SegmentationStorage : public NodeStorage {
 public:
  std::string Description() const override { return "segmentation (Slicer .seg.nrrd)"; }
  bool CanHandle(const vtkRPNode* node) const override {
    return node && const_cast<vtkRPNode*>(node)->IsA("vtkRPSegmentationNode");
  }
  std::vector<std::string> Extensions() const override { return {".seg.nrrd"}; }
  std::string NodeClassForFiles() const override { return "vtkRPSegmentationNode"; }
  int Priority() const override { return 10; }
  bool Write(vtkRPNode* node, const std::string& path, std::string& error) const override {
    return WriteSegmentationFile(path, vtkRPSegmentationNode::SafeDownCast(node), error);
  }
  bool Read(vtkRPNode* node, const std::string& path, std::string& error) const override {
    return ReadSegmentationFile(path, vtkRPSegmentationNode::SafeDownCast(node), error);
  }
};
}  // namespace

bool ReadSegmentationOrLabelmap(const std::string& path, vtkRPSegmentationNode* node, std::string& error) {
  // What `path` is comes from the loader (rpDataLoader.h), as for every reader: a node file that
  // holds an image is read here; a model, a scene, DICOM... is refused by name. Which image: a
  // Slicer segmentation by its header's keys (whatever its name), else a labelmap.
  if (const DataReader* reader = FindDataReader(path); reader && !IsVolumeFileName(path)) {
    const NodeStorage* storage = FindNodeStorageForFile(path);
    error = "'" + path + "' is a " + (storage ? storage->Description() : reader->Description()) +
            " file, not a segmentation or a labelmap volume";
    return false;
  }
  std::string segError;
  if (ReadSegmentationFile(path, node, segError) && node->GetNumberOfSegments() > 0) return true;
  if (!ReadVolumeFile(path, node, error)) {
    error = "cannot read the segmentation '" + path + "': " + (segError.empty() ? error : segError);
    return false;
  }
  if (!vtkRPSegmentationNode::IsLabelScalarType(node->GetImageData()->GetScalarType())) {
    error = "'" + path + "' is no segmentation: its voxels are not integer labels";
    return false;
  }
  vtkDataArray* scalars = node->GetImageData()->GetPointData()->GetScalars();
  std::set<long long> values;
  for (vtkIdType i = 0; i < scalars->GetNumberOfTuples() && values.size() < 255; ++i)
    if (const auto v = static_cast<long long>(scalars->GetTuple1(i)); v != 0) values.insert(v);
  const int previous = node->StartModify();
  node->RemoveAllSegments();
  for (long long v : values) {
    vtkRPSegmentationNode::Segment s;
    s.ID = std::to_string(v);
    s.Name = "Label " + s.ID;
    s.LabelValue = static_cast<int>(v);
    node->SetSegment(s);
  }
  node->EndModify(previous);
  return true;
}

std::shared_ptr<NodeStorage> MakeSegmentationStorage() { return std::make_shared<SegmentationStorage>(); }

}  // namespace rp
