#include "vtkRPSegmentationSliceDisplayableManager.h"

#include <algorithm>
#include <cmath>

#include <vtkImageActor.h>
#include <vtkImageData.h>
#include <vtkImageMapToColors.h>
#include <vtkImageMapper3D.h>
#include <vtkImageProperty.h>
#include <vtkImageReslice.h>
#include <vtkLookupTable.h>
#include <vtkMath.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkRenderer.h>

#include "rpView.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPViewState.h"

vtkStandardNewMacro(vtkRPSegmentationSliceDisplayableManager);

struct vtkRPSegmentationSliceDisplayableManager::Overlay {
  vtkNew<vtkImageReslice> Reslice;
  vtkNew<vtkMatrix4x4> Axes;
  vtkNew<vtkLookupTable> Table;
  vtkNew<vtkImageMapToColors> Map;
  vtkNew<vtkImageActor> Actor;
  vtkNew<vtkMatrix4x4> SliceToRAS;
  Overlay() {
    this->Reslice->SetOutputDimensionality(2);
    this->Reslice->SetInterpolationModeToNearestNeighbor();  // labels must not blend
    this->Reslice->SetBackgroundLevel(0);
    this->Reslice->SetResliceAxes(this->Axes);
    this->Map->SetLookupTable(this->Table);
    this->Map->SetOutputFormatToRGBA();
    this->Map->SetInputConnection(this->Reslice->GetOutputPort());
    this->Actor->GetMapper()->SetInputConnection(this->Map->GetOutputPort());
    this->Actor->InterpolateOff();
    this->Actor->SetUserMatrix(this->SliceToRAS);
    this->Actor->PickableOff();
  }
};

vtkRPSegmentationSliceDisplayableManager::~vtkRPSegmentationSliceDisplayableManager() { this->Finalize(); }

bool vtkRPSegmentationSliceDisplayableManager::CanDisplay(vtkRPNode* node) const {
  return vtkRPSegmentationNode::SafeDownCast(node) != nullptr;
}

vtkImageData* vtkRPSegmentationSliceDisplayableManager::GetOverlay(vtkRPNode* node) {
  auto it = this->Overlays.find(node);
  if (it == this->Overlays.end() || !it->second->Actor->GetVisibility()) return nullptr;
  it->second->Map->Update();
  return it->second->Map->GetOutput();
}

void vtkRPSegmentationSliceDisplayableManager::SetOpacity(double opacity) {
  this->Opacity = std::min(1.0, std::max(0.0, opacity));
  for (auto& entry : this->Overlays) entry.second->Actor->GetProperty()->SetOpacity(this->Opacity);
  this->RequestRender();
}

void vtkRPSegmentationSliceDisplayableManager::AddDisplay(vtkRPNode* node) {
  auto overlay = std::make_unique<Overlay>();
  overlay->Actor->GetProperty()->SetOpacity(this->Opacity);
  // Over the volumes (layer 0) and under the outlines, fiducials and tools of the overlay layer.
  this->GetView()->GetOverlayRenderer()->AddViewProp(overlay->Actor);
  this->Overlays[node] = std::move(overlay);
}

void vtkRPSegmentationSliceDisplayableManager::RemoveDisplay(vtkRPNode* node) {
  auto it = this->Overlays.find(node);
  if (it == this->Overlays.end()) return;
  if (this->GetView()) this->GetView()->GetOverlayRenderer()->RemoveViewProp(it->second->Actor);
  this->Overlays.erase(it);
}

void vtkRPSegmentationSliceDisplayableManager::UpdateDisplay(vtkRPNode* node) {
  auto* segmentation = vtkRPSegmentationNode::SafeDownCast(node);
  auto it = this->Overlays.find(node);
  if (!segmentation || it == this->Overlays.end()) return;
  Overlay& overlay = *it->second;
  vtkImageData* labels = segmentation->GetImageData();
  const bool visible = labels && labels->GetNumberOfPoints() > 0 && segmentation->GetNumberOfSegments() > 0;
  overlay.Actor->SetVisibility(visible);
  if (!visible) return;
  overlay.Reslice->SetInputData(labels);

  // One table entry per label value up to the largest segment's; unlisted labels transparent.
  int maxLabel = 0;
  for (const auto& segment : segmentation->GetSegments()) maxLabel = std::max(maxLabel, segment.LabelValue);
  const int entries = std::min(maxLabel, 65535) + 1;
  overlay.Table->SetNumberOfTableValues(entries);
  overlay.Table->SetTableRange(-0.5, entries - 0.5);  // value v → entry v
  for (int i = 0; i < entries; ++i) overlay.Table->SetTableValue(i, 0, 0, 0, 0);
  for (const auto& segment : segmentation->GetSegments()) {
    if (segment.LabelValue > 0 && segment.LabelValue < entries) {
      overlay.Table->SetTableValue(segment.LabelValue, segment.Color[0], segment.Color[1], segment.Color[2], 1.0);
    }
  }
  overlay.Table->Modified();
  this->UpdatePlane(overlay, node);
}

void vtkRPSegmentationSliceDisplayableManager::UpdatePlane(Overlay& overlay, vtkRPNode* node) {
  auto* segmentation = vtkRPSegmentationNode::SafeDownCast(node);
  rp::View* view = this->GetView();
  if (!segmentation || !segmentation->GetImageData() || !view->IsSlice()) return;
  const rp::SliceAxes axes = rp::GetSliceAxes(view->GetKind());
  const double offset = vtkMath::Dot(axes.Normal, this->GetViewState()->GetSlicePointRAS());
  for (int r = 0; r < 3; ++r) {
    overlay.SliceToRAS->SetElement(r, 0, axes.X[r]);
    overlay.SliceToRAS->SetElement(r, 1, axes.Y[r]);
    overlay.SliceToRAS->SetElement(r, 2, axes.Normal[r]);
    overlay.SliceToRAS->SetElement(r, 3, axes.Normal[r] * offset);
  }
  overlay.SliceToRAS->Modified();
  vtkNew<vtkMatrix4x4> toWorld, ijkToWorld, worldToIJK;
  segmentation->GetMatrixTransformToWorld(toWorld);
  vtkMatrix4x4::Multiply4x4(toWorld, segmentation->GetIJKToRASMatrix(), ijkToWorld);
  vtkMatrix4x4::Invert(ijkToWorld, worldToIJK);
  vtkMatrix4x4::Multiply4x4(worldToIJK, overlay.SliceToRAS, overlay.Axes);
  overlay.Axes->Modified();

  // Output grid: the labelmap's corners projected on the plane, at its finest spacing.
  int extent[6];
  segmentation->GetImageData()->GetExtent(extent);
  double xmin = VTK_DOUBLE_MAX, xmax = -VTK_DOUBLE_MAX, ymin = VTK_DOUBLE_MAX, ymax = -VTK_DOUBLE_MAX;
  for (int c = 0; c < 8; ++c) {
    double ijk[4] = {double(extent[(c & 1) ? 1 : 0]), double(extent[(c & 2) ? 3 : 2]), double(extent[(c & 4) ? 5 : 4]), 1}, ras[4];
    ijkToWorld->MultiplyPoint(ijk, ras);
    xmin = std::min(xmin, vtkMath::Dot(ras, axes.X));
    xmax = std::max(xmax, vtkMath::Dot(ras, axes.X));
    ymin = std::min(ymin, vtkMath::Dot(ras, axes.Y));
    ymax = std::max(ymax, vtkMath::Dot(ras, axes.Y));
  }
  double spacing[3];
  segmentation->GetSpacing(spacing);
  double step = std::max(1e-3, std::min({spacing[0], spacing[1], spacing[2]}));
  step = std::max(step, std::max(xmax - xmin, ymax - ymin) / 1023.0);
  overlay.Reslice->SetOutputOrigin(xmin, ymin, 0);
  overlay.Reslice->SetOutputSpacing(step, step, 1);
  overlay.Reslice->SetOutputExtent(0, static_cast<int>(std::ceil((xmax - xmin) / step)), 0,
                                   static_cast<int>(std::ceil((ymax - ymin) / step)), 0, 0);
}

void vtkRPSegmentationSliceDisplayableManager::OnViewStateModified() {
  for (auto& entry : this->Overlays) this->UpdatePlane(*entry.second, entry.first);
  this->RequestRender();
}
