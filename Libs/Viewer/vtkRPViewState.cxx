#include "vtkRPViewState.h"

#include <vtkObjectFactory.h>

vtkStandardNewMacro(vtkRPViewState);

namespace {
const char* const LayoutNames[] = {"4up", "3d", "axial", "sagittal", "coronal"};
}

const char* vtkRPViewState::GetLayoutAsString(int layout) {
  if (layout < LayoutFourUp || layout > LayoutOneUpCoronal) return "unknown";
  return LayoutNames[layout];
}

int vtkRPViewState::GetLayoutFromString(const std::string& text) {
  for (int i = LayoutFourUp; i <= LayoutOneUpCoronal; ++i) {
    if (text == LayoutNames[i]) return i;
  }
  return -1;
}

void vtkRPViewState::SetBackgroundVolumeID(const std::string& id) {
  if (id == this->BackgroundVolumeID) return;
  this->BackgroundVolumeID = id;
  this->Modified();
}

void vtkRPViewState::SetForegroundVolumeID(const std::string& id) {
  if (id == this->ForegroundVolumeID) return;
  this->ForegroundVolumeID = id;
  this->Modified();
}

void vtkRPViewState::SetActiveFiducialListID(const std::string& id) {
  if (id == this->ActiveFiducialListID) return;
  this->ActiveFiducialListID = id;
  this->Modified();
}

void vtkRPViewState::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SlicePointRAS: " << this->SlicePointRAS[0] << " " << this->SlicePointRAS[1] << " "
     << this->SlicePointRAS[2] << "\n";
  os << indent << "Layout: " << GetLayoutAsString(this->Layout) << "\n";
  os << indent << "BackgroundVolumeID: " << this->BackgroundVolumeID << "\n";
  os << indent << "ForegroundVolumeID: " << this->ForegroundVolumeID << "\n";
  os << indent << "ForegroundOpacity: " << this->ForegroundOpacity << "\n";
}
