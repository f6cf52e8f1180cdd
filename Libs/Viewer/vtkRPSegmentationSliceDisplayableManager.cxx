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
#include "vtkRPSliceLogic.h"
#include "vtkRPSliceNode.h"
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

void vtkRPSegmentationSliceDisplayableManager::AddDisplay(vtkRPNode* node) {
  auto overlay = std::make_unique<Overlay>();
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
  vtkRPSliceNode* sliceNode = this->GetSliceNode();
  const bool visible = labels && labels->GetNumberOfPoints() > 0 && segmentation->GetNumberOfSegments() > 0 &&
                       sliceNode && sliceNode->GetLabelNodeID() == segmentation->GetID();
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
  vtkRPSliceNode* sliceNode = this->GetSliceNode();
  if (!sliceNode) return;
  overlay.Actor->GetProperty()->SetOpacity(sliceNode->GetLabelOpacity());
  if (!overlay.Actor->GetVisibility()) return;
  sliceNode->GetSliceToRAS(overlay.SliceToRAS);
  vtkNew<vtkMatrix4x4> toWorld, ijkToWorld, worldToIJK;
  segmentation->GetMatrixTransformToWorld(toWorld);
  vtkMatrix4x4::Multiply4x4(toWorld, segmentation->GetIJKToRASMatrix(), ijkToWorld);
  vtkMatrix4x4::Invert(ijkToWorld, worldToIJK);
  vtkNew<vtkMatrix4x4> axes;
  vtkMatrix4x4::Multiply4x4(worldToIJK, overlay.SliceToRAS, axes);
  bool same = true;
  for (int i = 0; i < 16 && same; ++i) same = axes->GetData()[i] == overlay.Axes->GetData()[i];
  if (!same) overlay.Axes->DeepCopy(axes);  // an unchanged plane does not re-slice

  // Output grid: the labelmap's corners projected on the plane, at its finest spacing.
  double b[4];
  vtkRPSliceLogic::ComputePlaneBounds(segmentation, overlay.SliceToRAS, b);
  const double xmin = b[0], xmax = b[1], ymin = b[2], ymax = b[3];
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
  // The label layer may have changed (a newly shown segmentation needs its colours too).
  vtkRPSliceNode* sliceNode = this->GetSliceNode();
  for (auto& entry : this->Overlays) {
    const bool shown = sliceNode && sliceNode->GetLabelNodeID() == entry.first->GetID();
    if (shown != static_cast<bool>(entry.second->Actor->GetVisibility())) {
      this->UpdateDisplay(entry.first);
    } else {
      this->UpdatePlane(*entry.second, entry.first);
    }
  }
  this->RequestRender();
}
