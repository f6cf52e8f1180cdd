#include "vtkRPViewState.h"

#include <vtkObjectFactory.h>

#include "vtkRPLayoutNode.h"

vtkStandardNewMacro(vtkRPViewState);

// The layout names are the scene's layout node's.
const char* vtkRPViewState::GetLayoutAsString(int layout) { return vtkRPLayoutNode::GetArrangementAsString(layout); }

int vtkRPViewState::GetLayoutFromString(const std::string& text) { return vtkRPLayoutNode::GetArrangementFromString(text); }

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
