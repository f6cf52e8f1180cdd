#include "vtkRPSliceLogic.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <system_error>
#include <vector>

#include <vtkAlgorithmOutput.h>
#include <vtkCallbackCommand.h>
#include <vtkDataArray.h>
#include <vtkImageAlgorithm.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkMath.h>
#include <vtkMatrix4x4.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkUnsignedCharArray.h>

#include "rpSliceComposite.h"

#include "vtkRPImageNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPSliceNode.h"

vtkStandardNewMacro(vtkRPSliceLogic);

// The picture as a pipeline source (what the views update lazily when they render): the layers
// as the logic last set them, composited in one pass (rp::CompositeSlice). It keeps its own copy
// of what it draws, so a view holding its output never reaches into a deleted logic.
//
// Start() composites on a worker thread ahead of the render that needs the picture (the render
// scheduler starts the three pictures of a tick, then renders the views: the sagittal and
// coronal pictures are made while the axial view draws and waits for llvmpipe). The pipeline's
// RequestData then waits for that result instead of compositing. The worker reads only what
// Start() prepared on the calling thread (the layers' voxels, tables and the output array);
// Wait() is called before anything it reads may change, and the scheduler waits for every
// started picture before its tick ends, so no composite outlives the tick (volumes are edited
// between ticks, never during one).
class vtkRPSlicePicture : public vtkImageAlgorithm {
 public:
  static vtkRPSlicePicture* New();
  vtkTypeMacro(vtkRPSlicePicture, vtkImageAlgorithm);

  struct Layer {
    vtkSmartPointer<vtkImageData> Image;
    double PlaneToIJK[3][4] = {};
    bool Nearest = false;
    std::vector<std::uint32_t> Colors;
    double TableMin = 0, TableScale = 1, Opacity = 1;
  };
  std::vector<Layer> Layers;  // bottom first; Wait(), set them, then Modified()
  double Origin[2] = {0, 0};  // pixel (0, 0), plane coordinates
  double Spacing = 1;
  int Size[2] = {1, 1};
  int Executions = 0;
  int MadeAhead = 0;  // pictures RequestData took from a Start()ed composite

  // A volume's voxels changed in place count too.
  vtkMTimeType GetMTime() override {
    vtkMTimeType time = this->Superclass::GetMTime();
    for (const Layer& layer : this->Layers) {
      if (layer.Image) time = std::max(time, layer.Image->GetMTime());
    }
    return time;
  }

  /// Starts compositing on a worker thread if the picture is out of date and none is running.
  void Start() {
    if (this->Job.valid() || this->GetMTime() == this->MadeFor) return;
    this->JobFor = this->GetMTime();
    this->JobPixels = this->Prepare();
    try {
      this->Job = std::async(std::launch::async, [this]() { this->Composite(this->JobPixels, false); });
    } catch (const std::system_error&) {
      this->JobPixels = nullptr;  // no thread to be had: RequestData makes it as before
    }
  }
  /// Waits for a started composite (its result is kept for RequestData).
  void Wait() {
    if (this->Job.valid()) this->Job.get();
  }

 protected:
  vtkRPSlicePicture() { this->SetNumberOfInputPorts(0); }
  ~vtkRPSlicePicture() override { this->Wait(); }

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputs) override {
    vtkInformation* info = outputs->GetInformationObject(0);
    const int extent[6] = {0, this->Size[0] - 1, 0, this->Size[1] - 1, 0, 0};
    info->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
    info->Set(vtkDataObject::ORIGIN(), this->Origin[0], this->Origin[1], 0.0);
    info->Set(vtkDataObject::SPACING(), this->Spacing, this->Spacing, 1.0);
    vtkDataObject::SetPointDataActiveScalarInfo(info, VTK_UNSIGNED_CHAR, 4);
    return 1;
  }

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputs) override {
    vtkImageData* output = vtkImageData::GetData(outputs);
    output->SetExtent(0, this->Size[0] - 1, 0, this->Size[1] - 1, 0, 0);
    output->SetOrigin(this->Origin[0], this->Origin[1], 0);
    output->SetSpacing(this->Spacing, this->Spacing, 1);
    this->Wait();
    vtkSmartPointer<vtkUnsignedCharArray> pixels;
    if (this->JobPixels && this->JobFor == this->GetMTime()) {
      pixels = this->JobPixels;  // made ahead by Start()
      ++this->MadeAhead;
    } else {
      pixels = this->Prepare();
      this->Composite(pixels);
    }
    this->JobPixels = nullptr;
    output->GetPointData()->SetScalars(pixels);
    this->MadeFor = this->GetMTime();
    ++this->Executions;
    return 1;
  }

 private:
  vtkRPSlicePicture(const vtkRPSlicePicture&) = delete;
  void operator=(const vtkRPSlicePicture&) = delete;

  // On the calling thread: the layers as the compositor reads them (the layout copies made here
  // when missing) and the array it writes.
  vtkSmartPointer<vtkUnsignedCharArray> Prepare() {
    this->Prepared.clear();
    std::vector<const vtkImageData*> images;
    for (const Layer& layer : this->Layers) {
      rp::SliceLayer l = rp::SliceLayerOf(layer.Image, layer.PlaneToIJK, this->Origin, this->Spacing);
      if (!l.Scalars || layer.Colors.empty()) continue;
      l.Nearest = layer.Nearest;
      l.Table = layer.Colors.data();
      l.TableSize = static_cast<int>(layer.Colors.size());
      l.TableMin = layer.TableMin;
      l.TableScale = layer.TableScale;
      l.Opacity = layer.Opacity;
      this->Layouts.Apply(layer.Image, l);
      images.push_back(layer.Image);
      this->Prepared.push_back(l);
    }
    this->Layouts.Keep(images);
    auto pixels = vtkSmartPointer<vtkUnsignedCharArray>::New();
    pixels->SetNumberOfComponents(4);
    pixels->SetNumberOfTuples(static_cast<vtkIdType>(this->Size[0]) * this->Size[1]);
    return pixels;
  }

  // On any thread: reads only Prepared, writes only `pixels`. A worker composites alone (VTK
  // 9.1's vtkSMPTools keeps its "in a parallel region" flag unguarded: one thread at a time).
  void Composite(vtkUnsignedCharArray* pixels, bool parallel = true) {
    auto* picture = reinterpret_cast<std::uint32_t*>(pixels->GetPointer(0));
    if (this->Prepared.empty()) {
      std::fill(picture, picture + static_cast<std::size_t>(this->Size[0]) * this->Size[1], 0u);
    } else {
      rp::CompositeSlice(this->Prepared.data(), static_cast<int>(this->Prepared.size()), this->Size[0], this->Size[1],
                         picture, parallel);
    }
  }

  rp::SliceLayoutCache Layouts;
  std::vector<rp::SliceLayer> Prepared;
  std::future<void> Job;
  vtkSmartPointer<vtkUnsignedCharArray> JobPixels;
  vtkMTimeType JobFor = 0;   // the MTime the started composite is for
  vtkMTimeType MadeFor = 0;  // the MTime of the output
};
vtkStandardNewMacro(vtkRPSlicePicture);

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

double MinSpacing(vtkRPImageNode* volume) {
  double spacing[3];
  volume->GetSpacing(spacing);
  return std::max(1e-3, std::min({spacing[0], spacing[1], spacing[2]}));
}

}  // namespace

struct vtkRPSliceLogic::Layer {
  vtkWeakPointer<vtkImageData> Image;
  vtkNew<vtkMatrix4x4> Axes;  // plane coordinates → volume IJK
  bool Nearest = false;
  std::vector<std::uint32_t> Colors;  // RGBA8: value v → entry (v − TableMin) · TableScale
  double TableMin = 0, TableScale = 1;
  vtkWeakPointer<vtkRPImageNode> Volume;
  unsigned long Tags[2] = {0, 0};
  double TableKey[4] = {std::nan(""), 0, 0, 0};  // window, level, air threshold, background?
  vtkMTimeType ImageTime = 0;
  double AirThreshold = 0;
  vtkMTimeType AirThresholdImageTime = 0;
};

namespace {
// RGBA in [0, 1] as an RGBA8 word (R first in memory), rounded as vtkLookupTable stores it.
std::uint32_t PackColor(double r, double g, double b, double a) {
  auto byte = [](double v) { return static_cast<std::uint32_t>(std::clamp(v, 0.0, 1.0) * 255.0 + 0.5); };
  return byte(r) | byte(g) << 8 | byte(b) << 16 | byte(a) << 24;
}
}  // namespace

vtkRPSliceLogic::vtkRPSliceLogic() : Picture(vtkRPSlicePicture::New()) {
  for (Layer*& layer : this->Layers) layer = new Layer;
  this->Layers[2]->Nearest = true;  // labels must not blend
  this->Callback->SetClientData(this);
  this->Callback->SetCallback(&vtkRPSliceLogic::OnEvent);
}

vtkRPSliceLogic::~vtkRPSliceLogic() {
  this->SetSliceNode(nullptr, nullptr);
  this->ObserveLayers(nullptr, nullptr, nullptr);
  for (Layer* layer : this->Layers) delete layer;
  this->Picture->Delete();
}

void vtkRPSliceLogic::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Visible: " << this->Visible << " Reslices: " << this->GetNumberOfReslices() << "\n";
}

vtkAlgorithmOutput* vtkRPSliceLogic::GetOutputPort() { return this->Picture->GetOutputPort(); }

int vtkRPSliceLogic::GetNumberOfReslices() const { return this->Picture->Executions; }

void vtkRPSliceLogic::StartPicture() {
  if (this->Visible) this->Picture->Start();
}

void vtkRPSliceLogic::WaitForPicture() { this->Picture->Wait(); }

int vtkRPSliceLogic::GetNumberOfPicturesMadeAhead() const { return this->Picture->MadeAhead; }

void vtkRPSliceLogic::SetSliceNode(vtkRPScene* scene, vtkRPSliceNode* sliceNode) {
  if (this->SliceNode && this->SliceNodeTag) this->SliceNode->RemoveObserver(this->SliceNodeTag);
  this->SliceNodeTag = 0;
  this->Scene = scene;
  this->SliceNode = sliceNode;
  if (sliceNode) this->SliceNodeTag = sliceNode->AddObserver(vtkCommand::ModifiedEvent, this->Callback);
  this->Refresh();
}

void vtkRPSliceLogic::OnEvent(vtkObject*, unsigned long, void* clientData, void*) {
  auto* self = static_cast<vtkRPSliceLogic*>(clientData);
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

void vtkRPSliceLogic::ComputePlaneBounds(vtkRPImageNode* image, const vtkMatrix4x4* planeToRAS, double bounds[4],
                                         const int* part) {
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
  if (part) std::copy(part, part + 6, extent);
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

namespace {
// The IJK box of the non-zero voxels (false when there are none).
template <typename T>
bool NonZeroExtent(const T* voxels, const int dims[3], int extent[6]) {
  extent[0] = extent[2] = extent[4] = VTK_INT_MAX;
  extent[1] = extent[3] = extent[5] = VTK_INT_MIN;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j) {
      const T* row = voxels + (static_cast<size_t>(k) * dims[1] + j) * dims[0];
      int first = 0;
      while (first < dims[0] && row[first] == 0) ++first;
      if (first == dims[0]) continue;
      int last = dims[0] - 1;
      while (row[last] == 0) --last;
      const int box[6] = {first, last, j, j, k, k};
      for (int a = 0; a < 6; a += 2) {
        extent[a] = std::min(extent[a], box[a]);
        extent[a + 1] = std::max(extent[a + 1], box[a + 1]);
      }
    }
  return extent[0] <= extent[1];
}
}  // namespace

void vtkRPSliceLogic::ComputeShownExtent(vtkRPImageNode* image, int extent[6]) {
  vtkImageData* data = image->GetImageData();
  data->GetExtent(extent);
  if (!vtkRPSegmentationNode::SafeDownCast(image) || !data->GetPointData()->GetScalars() ||
      data->GetNumberOfScalarComponents() != 1)
    return;
  static vtkWeakPointer<vtkImageData> cachedImage;  // main thread, as the views
  static vtkMTimeType cachedTime = 0;
  static int cached[6];
  if (cachedImage != data || cachedTime != data->GetMTime()) {
    int dims[3], box[6];
    data->GetDimensions(dims);
    bool any = false;
    switch (data->GetScalarType()) {
      vtkTemplateMacro(any = NonZeroExtent(static_cast<const VTK_TT*>(data->GetScalarPointer()), dims, box));
    }
    for (int a = 0; a < 6; ++a) cached[a] = any ? extent[a - a % 2] + box[a] : extent[a];
    cachedImage = data;
    cachedTime = data->GetMTime();
  }
  std::copy(cached, cached + 6, extent);
}

void vtkRPSliceLogic::ComputeShownRASBounds(vtkRPImageNode* image, double bounds[6]) {
  int extent[6];
  ComputeShownExtent(image, extent);
  bounds[0] = bounds[2] = bounds[4] = VTK_DOUBLE_MAX;
  bounds[1] = bounds[3] = bounds[5] = -VTK_DOUBLE_MAX;
  for (int c = 0; c < 8; ++c) {
    const double ijk[4] = {double(extent[(c & 1) ? 1 : 0]), double(extent[(c & 2) ? 3 : 2]),
                           double(extent[(c & 4) ? 5 : 4]), 1.0};
    double ras[4];
    image->GetIJKToRASMatrix()->MultiplyPoint(ijk, ras);
    for (int a = 0; a < 3; ++a) {
      bounds[2 * a] = std::min(bounds[2 * a], ras[a]);
      bounds[2 * a + 1] = std::max(bounds[2 * a + 1], ras[a]);
    }
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
  if (layer.Image != image) {
    layer.Image = image;
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
    layer.Colors.resize(entries);
    layer.TableMin = first;
    layer.TableScale = entries / (last - first);
    for (int k = 0; k < entries; ++k) {
      const double value = first + (k + 0.5) * (last - first) / entries;
      const double grey = std::clamp((value - lo) / window, 0.0, 1.0);
      const double alpha = !isBackground || value >= layer.AirThreshold ? 1.0 : 0.0;
      layer.Colors[static_cast<size_t>(k)] = PackColor(grey, grey, grey, alpha);
    }
    changed = true;
  }
  return changed;
}

// The label layer: the segmentation's labels (nearest neighbour) to its segments' colours;
// label values without a segment (0 among them) are transparent.
bool vtkRPSliceLogic::UpdateLabelLayer(Layer& layer, vtkRPSegmentationNode* segmentation) {
  bool changed = false;
  vtkImageData* labels = segmentation->GetImageData();
  if (layer.Image != labels) {
    layer.Image = labels;
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
    layer.Colors.assign(static_cast<size_t>(entries), 0u);
    layer.TableMin = -0.5;  // value v → entry v
    layer.TableScale = 1.0;
    for (const auto& segment : segmentation->GetSegments()) {
      if (segment.LabelValue > 0 && segment.LabelValue < entries) {
        layer.Colors[static_cast<size_t>(segment.LabelValue)] =
            PackColor(segment.Color[0], segment.Color[1], segment.Color[2], 1.0);
      }
    }
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

  // A segmentation alone is drawn too (its labels over nothing), on its own grid.
  vtkRPImageNode* grid = background ? static_cast<vtkRPImageNode*>(background) : label;
  bool changed = (grid != nullptr) != this->Visible;
  this->Visible = grid != nullptr;
  if (node && node->GetSliceVisible() != this->SliceVisible) {
    this->SliceVisible = node->GetSliceVisible();
    changed = true;
  }
  if (!this->Visible) {
    if (changed) this->Modified();
    return;
  }

  // The plane is the node's; the grid covers both volumes (or the segmentation alone) projected
  // on it, at the background's finest spacing (at most MaxPixelsPerSide pixels a side).
  if (AssignIfDifferent(this->PlaneToRAS, node->GetSliceToRAS())) {
    this->PlaneToRAS->Modified();
    changed = true;
  }
  double xmin = VTK_DOUBLE_MAX, xmax = -VTK_DOUBLE_MAX, ymin = VTK_DOUBLE_MAX, ymax = -VTK_DOUBLE_MAX;
  for (vtkRPImageNode* volume : {grid, static_cast<vtkRPImageNode*>(foreground)}) {
    if (!volume) continue;
    double b[4];
    ComputePlaneBounds(volume, this->PlaneToRAS, b);
    xmin = std::min(xmin, b[0]);
    xmax = std::max(xmax, b[1]);
    ymin = std::min(ymin, b[2]);
    ymax = std::max(ymax, b[3]);
  }
  const double spacing = std::max(MinSpacing(grid), std::max(xmax - xmin, ymax - ymin) / (MaxPixelsPerSide - 1));
  const int nx = static_cast<int>(std::ceil((xmax - xmin) / spacing)) + 1;
  const int ny = static_cast<int>(std::ceil((ymax - ymin) / spacing)) + 1;
  const double bounds[4] = {xmin, xmin + (nx - 1) * spacing, ymin, ymin + (ny - 1) * spacing};
  if (!std::equal(bounds, bounds + 4, this->PlaneBounds) || spacing != this->PixelSpacing) {
    std::copy(bounds, bounds + 4, this->PlaneBounds);
    this->PixelSpacing = spacing;
    changed = true;
  }

  Layer* used[3] = {background ? this->Layers[0] : nullptr, foreground ? this->Layers[1] : nullptr,
                    label ? this->Layers[2] : nullptr};
  vtkRPScalarVolumeNode* volumes[2] = {background, foreground};
  for (int i = 0; i < 3; ++i) {
    if (!used[i]) continue;
    if (i < 2 ? this->UpdateLayer(*used[i], volumes[i], i == 0) : this->UpdateLabelLayer(*used[i], label)) changed = true;
  }
  // The background, the foreground over it, the labels over both, each with the node's opacity
  // (the picture keeps the first layer's alpha: the patient mask, or the labels when alone).
  std::vector<vtkRPSlicePicture::Layer> layers;
  for (int i = 0; i < 3; ++i) {
    if (!used[i]) continue;
    const Layer& layer = *used[i];
    vtkRPSlicePicture::Layer drawn;
    drawn.Image = layer.Image.GetPointer();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) drawn.PlaneToIJK[r][c] = layer.Axes->GetElement(r, c);
    drawn.Nearest = layer.Nearest;
    drawn.TableMin = layer.TableMin;
    drawn.TableScale = layer.TableScale;
    drawn.Opacity = i == 0 ? 1.0 : i == 1 ? node->GetForegroundOpacity() : node->GetLabelOpacity();
    layers.push_back(std::move(drawn));
  }
  vtkRPSlicePicture* picture = this->Picture;
  if (layers.size() != picture->Layers.size()) changed = true;
  for (size_t i = 0; i < layers.size() && !changed; ++i) {
    const auto& a = layers[i];
    const auto& b = picture->Layers[i];
    changed = a.Image != b.Image || a.Opacity != b.Opacity || a.Nearest != b.Nearest;
  }
  if (picture->Origin[0] != xmin || picture->Origin[1] != ymin || picture->Spacing != spacing ||
      picture->Size[0] != nx || picture->Size[1] != ny) {
    changed = true;
  }
  if (!changed) return;
  for (size_t i = 0, k = 0; i < 3; ++i) {
    if (used[i]) layers[k++].Colors = used[i]->Colors;
  }
  picture->Wait();  // a composite started ahead reads the layers
  picture->Layers = std::move(layers);
  picture->Origin[0] = xmin;
  picture->Origin[1] = ymin;
  picture->Spacing = spacing;
  picture->Size[0] = nx;
  picture->Size[1] = ny;
  picture->Modified();
  this->Modified();
}
