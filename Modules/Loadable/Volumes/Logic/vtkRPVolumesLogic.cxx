#include "vtkRPVolumesLogic.h"

#include <vtkNew.h>
#include <vtkObjectFactory.h>

#include "rpDataLoader.h"
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
  // The one loader (rpDataLoader.h): DICOM folder/DICOMDIR/file or any volume file.
  rp::ReadOptions read;
  read.Series = options.SeriesInstanceUID;
  read.ResampleIrregularSpacing = options.Dicom.ResampleIrregularSpacing;
  read.Progress = progress;
  const rp::DataReader* reader = rp::FindDataReader(path);
  if (reader && reader->ReadsIntoScene()) {
    error = "'" + path + "' is a " + reader->Description() + " file, not a volume";
    return nullptr;
  }
  rp::LoadResult loaded = rp::ReadPath(this->Scene, path, reader, read);
  // The one volume read (a DICOM folder may hold a segmentation of it too).
  std::vector<vtkRPScalarVolumeNode*> volumes;
  for (const auto& node : loaded.Nodes)
    if (auto* v = vtkRPScalarVolumeNode::SafeDownCast(node)) volumes.push_back(v);
  auto* volume = loaded.Ok && volumes.size() == 1 ? volumes.front() : nullptr;
  if (!volume) {
    error = !loaded.Ok          ? loaded.Error
            : volumes.empty()   ? "'" + path + "' is not a volume"
                                : "'" + path + "' holds " + std::to_string(volumes.size()) +
                                    " image series: choose one by its ID (roboplan dicom lists them)";
    return nullptr;
  }
  // The node is named from the file (extension dropped) or the series, unless `name` is given.
  volume->SetName(this->Scene->GenerateUniqueName(name.empty() ? volume->GetName() : name));
  return vtkRPScalarVolumeNode::SafeDownCast(this->Scene->AddNode(volume));
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
