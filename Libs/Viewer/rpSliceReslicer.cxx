#include "rpSliceReslicer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <vtkImageActor.h>
#include <vtkImageBlend.h>
#include <vtkImageData.h>
#include <vtkImageMapToColors.h>
#include <vtkImageMapper3D.h>
#include <vtkImageReslice.h>
#include <vtkLookupTable.h>
#include <vtkMath.h>
#include <vtkMatrix4x4.h>
#include <vtkPointData.h>

#include "vtkRPScalarVolumeNode.h"

namespace rp {

struct SliceReslicer::Layer {
  vtkNew<vtkImageReslice> Reslice;
  vtkNew<vtkLookupTable> Table;
  vtkNew<vtkImageMapToColors> Map;
  vtkNew<vtkMatrix4x4> Axes;
  Layer() {
    this->Reslice->SetOutputDimensionality(2);
    this->Reslice->SetInterpolationModeToLinear();
    // Float output with a NaN background: outside the volume maps to the table's NaN colour,
    // so the foreground is transparent there and the background black.
    this->Reslice->SetOutputScalarType(VTK_FLOAT);
    this->Reslice->SetBackgroundLevel(std::numeric_limits<double>::quiet_NaN());
    this->Reslice->SetResliceAxes(this->Axes);
    this->Table->SetRampToLinear();
    this->Table->SetHueRange(0, 0);
    this->Table->SetSaturationRange(0, 0);
    this->Table->SetValueRange(0, 1);
    this->Table->SetAlphaRange(1, 1);
    this->Table->SetNumberOfTableValues(256);
    this->Table->Build();
    this->Map->SetLookupTable(this->Table);
    this->Map->SetOutputFormatToRGBA();
    this->Map->SetInputConnection(this->Reslice->GetOutputPort());
  }
};

SliceReslicer::SliceReslicer(ViewKind orientation) : Orientation(orientation) {
  this->Layers[0] = new Layer;
  this->Layers[1] = new Layer;
  this->Blend->SetBlendModeToNormal();
  this->Actor->GetMapper()->SetInputConnection(this->Blend->GetOutputPort());
  this->Actor->InterpolateOn();
  this->Actor->SetUserMatrix(this->SliceToRAS);
  this->Actor->SetVisibility(false);
}

SliceReslicer::~SliceReslicer() {
  delete this->Layers[0];
  delete this->Layers[1];
}

void SliceReslicer::SetVolumes(vtkRPScalarVolumeNode* background, vtkRPScalarVolumeNode* foreground,
                               double foregroundOpacity) {
  if (!background && foreground) std::swap(background, foreground);
  this->Background = background;
  this->Foreground = foreground == background ? nullptr : foreground;
  this->ForegroundOpacity = foregroundOpacity;
}

void SliceReslicer::SetSlicePoint(const double pointRAS[3]) {
  std::copy(pointRAS, pointRAS + 3, this->SlicePoint);
}

namespace {

// World (RAS) bounds of a volume's voxel centres, with its parent transforms.
void VolumeCornersWorld(vtkRPScalarVolumeNode* volume, double corners[8][3]) {
  vtkNew<vtkMatrix4x4> toWorld, ijkToWorld;
  volume->GetMatrixTransformToWorld(toWorld);
  vtkMatrix4x4::Multiply4x4(toWorld, volume->GetIJKToRASMatrix(), ijkToWorld);
  int extent[6];
  volume->GetImageData()->GetExtent(extent);
  for (int c = 0; c < 8; ++c) {
    double ijk[4] = {double(extent[(c & 1) ? 1 : 0]), double(extent[(c & 2) ? 3 : 2]), double(extent[(c & 4) ? 5 : 4]), 1};
    double ras[4];
    ijkToWorld->MultiplyPoint(ijk, ras);
    std::copy(ras, ras + 3, corners[c]);
  }
}

double MinSpacing(vtkRPScalarVolumeNode* volume) {
  double spacing[3];
  volume->GetSpacing(spacing);
  return std::max(1e-3, std::min({spacing[0], spacing[1], spacing[2]}));
}

}  // namespace

void SliceReslicer::UpdateLayer(Layer& layer, vtkRPScalarVolumeNode* volume, bool transparentOutside) {
  // Reslice axes: output (slice) coordinates → RAS → volume IJK (data has origin 0, spacing 1).
  vtkNew<vtkMatrix4x4> toWorld, ijkToWorld, worldToIJK;
  volume->GetMatrixTransformToWorld(toWorld);
  vtkMatrix4x4::Multiply4x4(toWorld, volume->GetIJKToRASMatrix(), ijkToWorld);
  vtkMatrix4x4::Invert(ijkToWorld, worldToIJK);
  vtkMatrix4x4::Multiply4x4(worldToIJK, this->SliceToRAS, layer.Axes);
  layer.Axes->Modified();
  layer.Reslice->SetInputData(volume->GetImageData());

  const double window = std::max(1e-6, volume->GetWindow());
  const double level = volume->GetLevel();
  layer.Table->SetTableRange(level - 0.5 * window, level + 0.5 * window);
  layer.Table->SetNanColor(0, 0, 0, transparentOutside ? 0 : 1);
  layer.Table->Modified();
}

void SliceReslicer::Update() {
  vtkRPScalarVolumeNode* volumes[2] = {this->Background, this->Foreground};
  auto usable = [](vtkRPScalarVolumeNode* volume) {
    return volume && volume->GetImageData() && volume->GetImageData()->GetNumberOfPoints() > 0 &&
           volume->GetImageData()->GetPointData()->GetScalars() != nullptr;
  };
  if (!usable(this->Foreground)) volumes[1] = nullptr;
  if (!usable(this->Background)) {
    this->Actor->SetVisibility(false);  // an empty or scalar-less image shows nothing, quietly
    return;
  }
  const SliceAxes axes = GetSliceAxes(this->Orientation);

  // The plane: origin is the point of the plane closest to RAS 0, so pan along the plane does not
  // change the grid; the grid covers both volumes projected on the plane.
  const double offset = vtkMath::Dot(axes.Normal, this->SlicePoint);
  for (int r = 0; r < 3; ++r) {
    this->SliceToRAS->SetElement(r, 0, axes.X[r]);
    this->SliceToRAS->SetElement(r, 1, axes.Y[r]);
    this->SliceToRAS->SetElement(r, 2, axes.Normal[r]);
    this->SliceToRAS->SetElement(r, 3, axes.Normal[r] * offset);
  }
  this->SliceToRAS->Modified();

  double xmin = VTK_DOUBLE_MAX, xmax = -VTK_DOUBLE_MAX, ymin = VTK_DOUBLE_MAX, ymax = -VTK_DOUBLE_MAX;
  double spacing = MinSpacing(this->Background);
  for (vtkRPScalarVolumeNode* volume : volumes) {
    if (!volume) continue;
    double corners[8][3];
    VolumeCornersWorld(volume, corners);
    for (auto& corner : corners) {
      const double x = vtkMath::Dot(corner, axes.X), y = vtkMath::Dot(corner, axes.Y);
      xmin = std::min(xmin, x);
      xmax = std::max(xmax, x);
      ymin = std::min(ymin, y);
      ymax = std::max(ymax, y);
    }
  }
  // Keep the image a reasonable size whatever the volumes' extent (at most 1024 pixels a side).
  spacing = std::max(spacing, std::max(xmax - xmin, ymax - ymin) / 1023.0);
  this->PixelSpacing = spacing;
  const int nx = static_cast<int>(std::ceil((xmax - xmin) / spacing)) + 1;
  const int ny = static_cast<int>(std::ceil((ymax - ymin) / spacing)) + 1;

  this->Blend->RemoveAllInputs();
  for (int i = 0; i < 2; ++i) {
    vtkRPScalarVolumeNode* volume = volumes[i];
    if (!volume) continue;
    Layer& layer = *this->Layers[i];
    this->UpdateLayer(layer, volume, i == 1);
    layer.Reslice->SetOutputOrigin(xmin, ymin, 0);
    layer.Reslice->SetOutputSpacing(spacing, spacing, 1);
    layer.Reslice->SetOutputExtent(0, nx - 1, 0, ny - 1, 0, 0);
    this->Blend->AddInputConnection(layer.Map->GetOutputPort());
  }
  this->Blend->SetOpacity(0, 1.0);
  this->Blend->SetOpacity(1, this->ForegroundOpacity);
  this->Actor->SetVisibility(true);
}

}  // namespace rp
