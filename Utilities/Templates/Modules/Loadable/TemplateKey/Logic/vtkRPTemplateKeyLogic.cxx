#include "vtkRPTemplateKeyLogic.h"

#include <vtkObjectFactory.h>

#include "rpDataLoader.h"
#include "vtkRPNode.h"
#include "vtkRPScene.h"

vtkStandardNewMacro(vtkRPTemplateKeyLogic);

void vtkRPTemplateKeyLogic::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Scene: " << this->Scene << "\n";
}

bool vtkRPTemplateKeyLogic::LoadFiles(const std::vector<std::string>& paths, std::string& error) {
  if (!this->Scene) {
    error = "TemplateKey logic has no scene";
    return false;
  }
  for (const std::string& path : paths) {
    const rp::LoadResult result = rp::LoadPath(this->Scene, path);
    if (!result.Ok) {
      error = result.Error;
      return false;
    }
  }
  return true;
}

std::map<std::string, int> vtkRPTemplateKeyLogic::CountNodesByClass() const {
  std::map<std::string, int> counts;
  if (!this->Scene) return counts;
  for (int i = 0; i < this->Scene->GetNumberOfNodes(); ++i) ++counts[this->Scene->GetNthNode(i)->GetClassName()];
  return counts;
}
