#include "vtkRPVolumesLogic.h"

#include <filesystem>

#include <vtkNew.h>
#include <vtkObjectFactory.h>

#include "vtkRPLinearTransformNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"

vtkStandardNewMacro(vtkRPVolumesLogic);

void vtkRPVolumesLogic::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Scene: " << this->Scene << "\n";
}

vtkRPScalarVolumeNode* vtkRPVolumesLogic::AddVolume(const rp::ImageVolume& volume, const std::string& name) {
  if (!this->Scene || volume.Empty()) return nullptr;
  vtkNew<vtkRPScalarVolumeNode> node;
  node->SetName(this->Scene->GenerateUniqueName(name.empty() ? std::string("Volume") : name));
  rp::CopyToNode(volume, node.GetPointer());
  return vtkRPScalarVolumeNode::SafeDownCast(this->Scene->AddNode(node));
}

vtkRPScalarVolumeNode* vtkRPVolumesLogic::LoadVolume(const std::string& path, const std::string& name,
                                                     std::string& error, const rp::VolumeReadOptions& options,
                                                     const rp::ProgressCallback& progress) {
  if (!this->Scene) {
    error = "volumes logic has no scene";
    return nullptr;
  }
  rp::ImageVolume volume;
  if (!rp::ReadVolume(path, volume, error, options, nullptr, progress)) return nullptr;
  std::string nodeName = name;
  if (nodeName.empty()) {
    nodeName = std::filesystem::path(path).filename().string();
    for (const char* ext : {".nii.gz", ".nrrd", ".nhdr", ".nii", ".mha", ".mhd"}) {
      const std::string e = ext;
      if (nodeName.size() > e.size() && nodeName.compare(nodeName.size() - e.size(), e.size(), e) == 0) {
        nodeName.resize(nodeName.size() - e.size());
        break;
      }
    }
  }
  return this->AddVolume(volume, nodeName);
}

vtkRPLinearTransformNode* vtkRPVolumesLogic::RegisterVolumes(vtkRPScalarVolumeNode* fixed, vtkRPScalarVolumeNode* moving,
                                                             const rp::RigidRegistrationOptions& options,
                                                             rp::RigidRegistrationResult& result, std::string& error,
                                                             const rp::ProgressCallback& progress,
                                                             const std::atomic<bool>* cancel) {
  if (!this->Scene || !fixed || !moving) {
    error = "registration needs a scene, a fixed and a moving volume";
    return nullptr;
  }
  if (fixed == moving) {
    error = "the fixed and the moving volume are the same node";
    return nullptr;
  }
  if (!rp::RegisterVolumesRigid(rp::FromNode(fixed), rp::FromNode(moving), options, result, error, progress, cancel))
    return nullptr;
  if (!result.Converged) {
    error = "registration did not converge (" + result.StopReason + "); the result was not applied";
    return nullptr;
  }
  vtkNew<vtkRPLinearTransformNode> transform;
  transform->SetName(this->Scene->GenerateUniqueName(moving->GetName() + "To" + fixed->GetName()));
  transform->SetMatrixTransformToParent(result.MovingToFixed);
  auto* added = vtkRPLinearTransformNode::SafeDownCast(this->Scene->AddNode(transform));
  // The fixed volume's own parent (if any) carries both into the world.
  if (added && !fixed->GetTransformNodeID().empty()) added->SetAndObserveTransformNodeID(fixed->GetTransformNodeID());
  if (added) moving->SetAndObserveTransformNodeID(added->GetID());
  return added;
}
