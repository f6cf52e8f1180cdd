#include "vtkRPSliceLogic.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <vtkAlgorithmOutput.h>
#include <vtkCallbackCommand.h>
#include <vtkDataArray.h>
#include <vtkImageBlend.h>
#include <vtkImageData.h>
#include <vtkImageResliceToColors.h>
#include <vtkLookupTable.h>
#include <vtkMath.h>
#include <vtkMatrix4x4.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>

#include "vtkRPImageNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPSliceNode.h"

vtkStandardNewMacro(vtkRPSliceLogic);

namespace {

constexpr int MaxPixelsPerSide = 1024;

bool Usable(vtkRPScalarVolumeNode* volume) {
  vtkImageData* image = volume ? volume->GetImageData() : nullptr;
  return image && image->GetNumberOfPoints() > 0 && image->GetPointData()->GetScalars() != nullptr;
}

// Copies `source` into `target` and returns true when any element differs (so an unchanged
// matrix never marks the pipeline modified).
bool AssignIfDifferent(vtkMatrix4x4* target, const vtkMatrix4x4* source) {
  bool same = true;
  for (int r = 0; r < 4 && same; ++r)
    for (int c = 0; c < 4 && same; ++c) same = target->GetElement(r, c) == source->GetElement(r, c);
  if (same) return false;
  target->DeepCopy(source);
  return true;
}

void VolumeIJKToWorld(vtkRPImageNode* volume, vtkMatrix4x4* ijkToWorld) {
  vtkNew<vtkMatrix4x4> toWorld;
  volume->GetMatrixTransformToWorld(toWorld);
  vtkMatrix4x4::Multiply4x4(toWorld, volume->GetIJKToRASMatrix(), ijkToWorld);
}

double MinSpacing(vtkRPScalarVolumeNode* volume) {
  double spacing[3];
  volume->GetSpacing(spacing);
  return std::max(1e-3, std::min({spacing[0], spacing[1], spacing[2]}));
}

}  // namespace

struct vtkRPSliceLogic::Layer {
  vtkNew<vtkImageResliceToColors> Reslice;
  vtkNew<vtkLookupTable> Table;
  vtkNew<vtkMatrix4x4> Axes;  // plane coordinates → volume IJK
  vtkWeakPointer<vtkRPImageNode> Volume;
  unsigned long Tags[2] = {0, 0};
  double TableKey[4] = {std::nan(""), 0, 0, 0};  // window, level, air threshold, background?
  vtkMTimeType ImageTime = 0;
  double AirThreshold = 0;
  vtkMTimeType AirThresholdImageTime = 0;
  Layer() {
    this->Reslice->SetOutputDimensionality(2);
    this->Reslice->SetInterpolationModeToLinear();
    this->Reslice->SetResliceAxes(this->Axes);
    this->Reslice->SetLookupTable(this->Table);
    this->Reslice->SetOutputFormatToRGBA();
    this->Reslice->SetBackgroundColor(0, 0, 0, 0);  // outside the volume: transparent
  }
};

vtkRPSliceLogic::vtkRPSliceLogic() {
  for (Layer*& layer : this->Layers) layer = new Layer;
  this->Layers[2]->Reslice->SetInterpolationModeToNearestNeighbor();  // labels must not blend
  this->Blend->SetBlendModeToNormal();  // keeps the first input's alpha: the patient mask
  this->Callback->SetClientData(this);
  this->Callback->SetCallback(&vtkRPSliceLogic::OnEvent);
  this->ResliceTag = this->Layers[0]->Reslice->AddObserver(vtkCommand::EndEvent, this->Callback);
}

vtkRPSliceLogic::~vtkRPSliceLogic() {
  this->SetSliceNode(nullptr, nullptr);
  this->ObserveLayers(nullptr, nullptr, nullptr);
  this->Layers[0]->Reslice->RemoveObserver(this->ResliceTag);
  for (Layer* layer : this->Layers) delete layer;
}

void vtkRPSliceLogic::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Visible: " << this->Visible << " Reslices: " << this->ResliceCount << "\n";
}

vtkAlgorithmOutput* vtkRPSliceLogic::GetOutputPort() { return this->Blend->GetOutputPort(); }

void vtkRPSliceLogic::SetSliceNode(vtkRPScene* scene, vtkRPSliceNode* sliceNode) {
  if (this->SliceNode && this->SliceNodeTag) this->SliceNode->RemoveObserver(this->SliceNodeTag);
  this->SliceNodeTag = 0;
  this->Scene = scene;
  this->SliceNode = sliceNode;
  if (sliceNode) this->SliceNodeTag = sliceNode->AddObserver(vtkCommand::ModifiedEvent, this->Callback);
  this->Refresh();
}

void vtkRPSliceLogic::OnEvent(vtkObject* caller, unsigned long event, void* clientData, void*) {
  auto* self = static_cast<vtkRPSliceLogic*>(clientData);
  if (event == vtkCommand::EndEvent && caller == self->Layers[0]->Reslice.GetPointer()) {
    ++self->ResliceCount;
    return;
  }
  self->Refresh();
}

void vtkRPSliceLogic::ObserveLayers(vtkRPScalarVolumeNode* background, vtkRPScalarVolumeNode* foreground,
                                    vtkRPSegmentationNode* label) {
  vtkRPImageNode* nodes[3] = {background, foreground, label};
  for (int i = 0; i < 3; ++i) {
    Layer& layer = *this->Layers[i];
    if (layer.Volume == nodes[i]) continue;
    if (layer.Volume) {
      for (unsigned long tag : layer.Tags) layer.Volume->RemoveObserver(tag);
    }
    layer.Volume = nodes[i];
    if (nodes[i]) {
      layer.Tags[0] = nodes[i]->AddObserver(vtkCommand::ModifiedEvent, this->Callback);
      layer.Tags[1] = nodes[i]->AddObserver(vtkRPNode::TransformModifiedEvent, this->Callback);
    }
  }
}

void vtkRPSliceLogic::ComputePlaneBounds(vtkRPImageNode* image, const vtkMatrix4x4* planeToRAS, double bounds[4]) {
  double x[3], y[3], origin[3];
  for (int r = 0; r < 3; ++r) {
    x[r] = planeToRAS->GetElement(r, 0);
    y[r] = planeToRAS->GetElement(r, 1);
    origin[r] = planeToRAS->GetElement(r, 3);
  }
  vtkNew<vtkMatrix4x4> ijkToWorld;
  VolumeIJKToWorld(image, ijkToWorld);
  int extent[6];
  image->GetImageData()->GetExtent(extent);
  bounds[0] = bounds[2] = VTK_DOUBLE_MAX;
  bounds[1] = bounds[3] = -VTK_DOUBLE_MAX;
  for (int c = 0; c < 8; ++c) {
    const double ijk[4] = {double(extent[(c & 1) ? 1 : 0]), double(extent[(c & 2) ? 3 : 2]), double(extent[(c & 4) ? 5 : 4]), 1};
    double ras[4];
    ijkToWorld->MultiplyPoint(ijk, ras);
    const double d[3] = {ras[0] - origin[0], ras[1] - origin[1], ras[2] - origin[2]};
    bounds[0] = std::min(bounds[0], vtkMath::Dot(d, x));
    bounds[1] = std::max(bounds[1], vtkMath::Dot(d, x));
    bounds[2] = std::min(bounds[2], vtkMath::Dot(d, y));
    bounds[3] = std::max(bounds[3], vtkMath::Dot(d, y));
  }
}

double vtkRPSliceLogic::ComputeAirThreshold(vtkRPScalarVolumeNode* volume) {
  vtkImageData* image = volume ? volume->GetImageData() : nullptr;
  vtkDataArray* scalars = image ? image->GetPointData()->GetScalars() : nullptr;
  if (!scalars || scalars->GetNumberOfTuples() == 0) return 0.0;
  double range[2];
  scalars->GetRange(range, 0);
  if (range[0] <= -900.0) return -400.0;  // Hounsfield units: between air (−1000) and fat (−100)
  const vtkIdType count = scalars->GetNumberOfTuples();
  const vtkIdType stride = std::max<vtkIdType>(1, count / 100000);
  std::vector<double> sample;
  sample.reserve(static_cast<size_t>(count / stride + 1));
  for (vtkIdType i = 0; i < count; i += stride) sample.push_back(scalars->GetComponent(i, 0));
  const size_t low = sample.size() / 100, high = sample.size() - 1 - sample.size() / 100;
  std::nth_element(sample.begin(), sample.begin() + static_cast<long>(low), sample.end());
  const double p1 = sample[low];
  std::nth_element(sample.begin(), sample.begin() + static_cast<long>(high), sample.end());
  const double p99 = sample[high];
  return p1 + 0.1 * (p99 - p1);
}

// Re-reads one layer's volume: reslice axes, input and colour table. True when the picture changes.
bool vtkRPSliceLogic::UpdateLayer(Layer& layer, vtkRPScalarVolumeNode* volume, bool isBackground) {
  bool changed = false;
  vtkImageData* image = volume->GetImageData();
  if (layer.Reslice->GetInput() != image) {
    layer.Reslice->SetInputData(image);
    changed = true;
  }
  if (image->GetMTime() != layer.ImageTime) {
    layer.ImageTime = image->GetMTime();
    changed = true;
  }
  vtkNew<vtkMatrix4x4> ijkToWorld, worldToIJK, axes;
  VolumeIJKToWorld(volume, ijkToWorld);
  vtkMatrix4x4::Invert(ijkToWorld, worldToIJK);
  vtkMatrix4x4::Multiply4x4(worldToIJK, this->PlaneToRAS, axes);
  if (AssignIfDifferent(layer.Axes, axes)) {
    layer.Axes->Modified();
    changed = true;
  }

  if (isBackground && layer.AirThresholdImageTime != image->GetMTime()) {
    layer.AirThreshold = ComputeAirThreshold(volume);
    layer.AirThresholdImageTime = image->GetMTime();
  }
  const double window = std::max(1e-6, volume->GetWindow()), level = volume->GetLevel();
  const double key[4] = {window, level, isBackground ? layer.AirThreshold : 0.0, isBackground ? 1.0 : 0.0};
  if (!std::equal(key, key + 4, layer.TableKey)) {
    std::copy(key, key + 4, layer.TableKey);
    // Grey ramp over the window. The background also maps air (below the threshold) to
    // alpha 0, so the table reaches down to the threshold when it lies below the window.
    const double lo = level - 0.5 * window, hi = level + 0.5 * window;
    double first = lo, last = hi;
    if (isBackground) {
      const double margin = 0.01 * window;
      first = std::min(lo, layer.AirThreshold - margin);
      last = std::max(hi, layer.AirThreshold + margin);
    }
    const int entries = 1024;
    layer.Table->SetNumberOfTableValues(entries);
    layer.Table->SetTableRange(first, last);
    for (int k = 0; k < entries; ++k) {
      const double value = first + (k + 0.5) * (last - first) / entries;
      const double grey = std::clamp((value - lo) / window, 0.0, 1.0);
      const double alpha = !isBackground || value >= layer.AirThreshold ? 1.0 : 0.0;
      layer.Table->SetTableValue(k, grey, grey, grey, alpha);
    }
    layer.Table->Modified();
    changed = true;
  }
  return changed;
}

// The label layer: the segmentation's labels (nearest neighbour) to its segments' colours;
// label values without a segment (0 among them) are transparent.
bool vtkRPSliceLogic::UpdateLabelLayer(Layer& layer, vtkRPSegmentationNode* segmentation) {
  bool changed = false;
  vtkImageData* labels = segmentation->GetImageData();
  if (layer.Reslice->GetInput() != labels) {
    layer.Reslice->SetInputData(labels);
    changed = true;
  }
  if (labels->GetMTime() != layer.ImageTime) {
    layer.ImageTime = labels->GetMTime();
    changed = true;
  }
  vtkNew<vtkMatrix4x4> ijkToWorld, worldToIJK, axes;
  VolumeIJKToWorld(segmentation, ijkToWorld);
  vtkMatrix4x4::Invert(ijkToWorld, worldToIJK);
  vtkMatrix4x4::Multiply4x4(worldToIJK, this->PlaneToRAS, axes);
  if (AssignIfDifferent(layer.Axes, axes)) {
    layer.Axes->Modified();
    changed = true;
  }
  // The segment table is the node's: rebuilt when the node changed (names, colours, labels).
  const double key[4] = {double(segmentation->GetMTime()), 0, 0, 2};
  if (!std::equal(key, key + 4, layer.TableKey)) {
    std::copy(key, key + 4, layer.TableKey);
    int maxLabel = 0;
    for (const auto& segment : segmentation->GetSegments()) maxLabel = std::max(maxLabel, segment.LabelValue);
    const int entries = std::min(maxLabel, 65535) + 1;
    layer.Table->SetNumberOfTableValues(entries);
    layer.Table->SetTableRange(-0.5, entries - 0.5);  // value v → entry v
    for (int i = 0; i < entries; ++i) layer.Table->SetTableValue(i, 0, 0, 0, 0);
    for (const auto& segment : segmentation->GetSegments()) {
      if (segment.LabelValue > 0 && segment.LabelValue < entries) {
        layer.Table->SetTableValue(segment.LabelValue, segment.Color[0], segment.Color[1], segment.Color[2], 1.0);
      }
    }
    layer.Table->Modified();
    changed = true;
  }
  return changed;
}

void vtkRPSliceLogic::Refresh() {
  vtkRPScene* scene = this->Scene;
  vtkRPSliceNode* node = this->SliceNode;
  auto resolve = [scene](const std::string& id) {
    return scene && !id.empty() ? vtkRPScalarVolumeNode::SafeDownCast(scene->GetNodeByID(id)) : nullptr;
  };
  vtkRPScalarVolumeNode* background = node ? resolve(node->GetBackgroundVolumeID()) : nullptr;
  vtkRPScalarVolumeNode* foreground = node ? resolve(node->GetForegroundVolumeID()) : nullptr;
  if (!Usable(background)) background = nullptr;
  if (!Usable(foreground) || foreground == background) foreground = nullptr;
  if (!background && foreground) std::swap(background, foreground);
  auto* label = scene && node ? vtkRPSegmentationNode::SafeDownCast(scene->GetNodeByID(node->GetLabelNodeID())) : nullptr;
  if (label && (!label->GetImageData() || label->GetImageData()->GetNumberOfPoints() == 0 ||
                !label->GetImageData()->GetPointData()->GetScalars() || label->GetNumberOfSegments() == 0)) {
    label = nullptr;
  }
  this->ObserveLayers(background, foreground, label);

  bool changed = (background != nullptr) != this->Visible;
  this->Visible = background != nullptr;
  if (node && node->GetSliceVisible() != this->SliceVisible) {
    this->SliceVisible = node->GetSliceVisible();
    changed = true;
  }
  if (!this->Visible) {
    if (changed) this->Modified();
    return;
  }

  // The plane is the node's; the grid covers both volumes projected on it, at the background's
  // finest spacing (at most MaxPixelsPerSide pixels a side).
  if (AssignIfDifferent(this->PlaneToRAS, node->GetSliceToRAS())) {
    this->PlaneToRAS->Modified();
    changed = true;
  }
  double xmin = VTK_DOUBLE_MAX, xmax = -VTK_DOUBLE_MAX, ymin = VTK_DOUBLE_MAX, ymax = -VTK_DOUBLE_MAX;
  for (vtkRPScalarVolumeNode* volume : {background, foreground}) {
    if (!volume) continue;
    double b[4];
    ComputePlaneBounds(volume, this->PlaneToRAS, b);
    xmin = std::min(xmin, b[0]);
    xmax = std::max(xmax, b[1]);
    ymin = std::min(ymin, b[2]);
    ymax = std::max(ymax, b[3]);
  }
  const double spacing = std::max(MinSpacing(background), std::max(xmax - xmin, ymax - ymin) / (MaxPixelsPerSide - 1));
  const int nx = static_cast<int>(std::ceil((xmax - xmin) / spacing)) + 1;
  const int ny = static_cast<int>(std::ceil((ymax - ymin) / spacing)) + 1;
  const double bounds[4] = {xmin, xmin + (nx - 1) * spacing, ymin, ymin + (ny - 1) * spacing};
  if (!std::equal(bounds, bounds + 4, this->PlaneBounds) || spacing != this->PixelSpacing) {
    std::copy(bounds, bounds + 4, this->PlaneBounds);
    this->PixelSpacing = spacing;
    changed = true;
  }

  Layer* used[3] = {this->Layers[0], foreground ? this->Layers[1] : nullptr, label ? this->Layers[2] : nullptr};
  vtkRPScalarVolumeNode* volumes[2] = {background, foreground};
  for (int i = 0; i < 3; ++i) {
    if (!used[i]) continue;
    Layer& layer = *used[i];
    if (i < 2 ? this->UpdateLayer(layer, volumes[i], i == 0) : this->UpdateLabelLayer(layer, label)) changed = true;
    double previousOrigin[3], previousSpacing[3];
    int previousExtent[6];
    layer.Reslice->GetOutputOrigin(previousOrigin);
    layer.Reslice->GetOutputSpacing(previousSpacing);
    layer.Reslice->GetOutputExtent(previousExtent);
    if (previousOrigin[0] != xmin || previousOrigin[1] != ymin || previousSpacing[0] != spacing ||
        previousExtent[1] != nx - 1 || previousExtent[3] != ny - 1 || previousExtent[0] != 0 || previousExtent[2] != 0) {
      layer.Reslice->SetOutputOrigin(xmin, ymin, 0);
      layer.Reslice->SetOutputSpacing(spacing, spacing, 1);
      layer.Reslice->SetOutputExtent(0, nx - 1, 0, ny - 1, 0, 0);
    }
  }
  // Blend inputs: the background, the foreground over it, the labels over both, each with the
  // node's opacity (the output keeps the background's alpha: the patient mask).
  std::vector<vtkAlgorithmOutput*> inputs;
  std::vector<double> opacities;
  for (int i = 0; i < 3; ++i) {
    if (!used[i]) continue;
    inputs.push_back(used[i]->Reslice->GetOutputPort());
    opacities.push_back(i == 0 ? 1.0 : i == 1 ? node->GetForegroundOpacity() : node->GetLabelOpacity());
  }
  bool sameInputs = this->Blend->GetNumberOfInputConnections(0) == static_cast<int>(inputs.size());
  for (size_t i = 0; i < inputs.size() && sameInputs; ++i) sameInputs = this->Blend->GetInputConnection(0, static_cast<int>(i)) == inputs[i];
  if (!sameInputs) {
    this->Blend->RemoveAllInputs();
    for (vtkAlgorithmOutput* input : inputs) this->Blend->AddInputConnection(input);
    changed = true;
  }
  for (size_t i = 1; i < opacities.size(); ++i) {
    if (this->Blend->GetOpacity(static_cast<int>(i)) != opacities[i]) {
      this->Blend->SetOpacity(static_cast<int>(i), opacities[i]);
      changed = true;
    }
  }
  if (changed) this->Modified();
}
