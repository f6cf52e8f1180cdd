#include "vtkRPViewState.h"

#include <vtkObjectFactory.h>

vtkStandardNewMacro(vtkRPViewState);

void vtkRPViewState::SetActiveFiducialListID(const std::string& id) {
  if (id == this->ActiveFiducialListID) return;
  this->ActiveFiducialListID = id;
  this->Modified();
}

void vtkRPViewState::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "InteractionMode: " << this->InteractionMode << "\n";
  os << indent << "ActiveFiducialListID: " << this->ActiveFiducialListID << "\n";
}
