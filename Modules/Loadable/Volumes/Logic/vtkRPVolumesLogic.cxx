#include "vtkRPVolumesLogic.h"

#include <filesystem>

#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>

#include "rpDataLoader.h"
#include "rpDicomEntries.h"
#include "rpModelIO.h"
#include "rpTransformIO.h"
#include "rpVolumeIO.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"

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
                                                     const rp::ProgressCallback& progress,
                                                     std::vector<std::string>* warnings) {
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
  if (warnings) warnings->insert(warnings->end(), loaded.Warnings.begin(), loaded.Warnings.end());
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

vtkRPNode* vtkRPVolumesLogic::LoadLabelmap(const std::string& path, std::string& error) {
  if (!this->Scene) {
    error = "volumes logic has no scene";
    return nullptr;
  }
  rp::LoadResult loaded;
  vtkRPNode* node = rp::LoadSingleNode(this->Scene, path, loaded);
  if (!node) {
    error = loaded.Error;
    return nullptr;
  }
  if (vtkRPSegmentationNode::SafeDownCast(node) || vtkRPScalarVolumeNode::SafeDownCast(node)) return node;
  this->Scene->RemoveNode(node);
  error = "'" + path + "' is neither a segmentation nor a labelmap volume";
  return nullptr;
}

namespace {
// A labelmap node as a volume, with its segments' names by label value.
bool LabelsOf(vtkRPNode* node, rp::ImageVolume& volume, std::map<int, vtkRPVolumesLogic::LabelName>& names) {
  if (auto* segmentation = vtkRPSegmentationNode::SafeDownCast(node)) {
    volume = rp::FromNode(segmentation);
    for (const auto& s : segmentation->GetSegments()) names[s.LabelValue] = {s.ID, s.Name};
    return true;
  }
  if (auto* image = vtkRPScalarVolumeNode::SafeDownCast(node)) {
    volume = rp::FromNode(image);
    return true;
  }
  return false;
}
}  // namespace

bool vtkRPVolumesLogic::CompareLabels(vtkRPNode* segmentation, vtkRPNode* truth, const std::vector<int>& labels,
                                      LabelScores& scores, std::string& error) {
  rp::ImageVolume test, reference;
  LabelScores result;
  if (!LabelsOf(segmentation, test, result.Names) || !LabelsOf(truth, reference, result.TruthNames)) {
    error = "comparing labels needs two segmentation or labelmap volume nodes";
    return false;
  }
  if (!rp::CompareLabels(test, reference, labels, result.Comparison, error)) return false;
  scores = std::move(result);
  return true;
}

bool vtkRPVolumesLogic::WriteKneePhantom(const rp::KneePhantomOptions& options, const std::string& folder, bool dicom,
                                         KneePhantomFiles& files, std::string& error,
                                         const rp::ProgressCallback& progress) {
  namespace fs = std::filesystem;
  KneePhantomFiles written;
  rp::KneePhantom& phantom = written.Phantom;
  if (!rp::GenerateKneePhantom(options, phantom, error, progress)) return false;
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (!fs::is_directory(folder)) {
    error = "cannot create " + folder;
    return false;
  }
  const fs::path root(folder);
  written.CT = (root / (dicom ? "CT" : "ct.nrrd")).string();
  written.MR = (root / (dicom ? "MR" : "mr.nrrd")).string();
  written.Labels = (root / "labels.nrrd").string();
  written.TruthTransform = (root / "MRToCT-truth.tfm").string();
  rp::DicomWriteOptions ctOptions, mrOptions;
  ctOptions.Modality = "CT";
  ctOptions.SeriesDescription = phantom.CT.Description;
  ctOptions.SeriesNumber = 1;
  mrOptions.Modality = "MR";
  mrOptions.SeriesDescription = phantom.MR.Description;
  mrOptions.SeriesNumber = 2;
  mrOptions.PatientName = ctOptions.PatientName;
  mrOptions.PatientID = ctOptions.PatientID;
  if (dicom) {
    for (const char* sub : {"CT", "MR"}) fs::remove_all(root / sub, ec);  // no stale slices
  }
  if (!rp::WriteVolume(written.CT, phantom.CT, error, ctOptions, progress) ||
      !rp::WriteVolume(written.MR, phantom.MR, error, mrOptions, progress) ||
      !rp::WriteVolumeFile(written.Labels, phantom.Labels.Image, phantom.Labels.IJKToRAS, {}, error))
    return false;
  // The true surfaces (in the CT's RAS, written as LPS model files like every model).
  for (int s = 0; s < rp::KneeStructureCount; ++s) {
    const auto structure = static_cast<rp::KneeStructure>(s);
    vtkSmartPointer<vtkPolyData> surface = phantom.Model->Surface(structure);
    if (!surface) continue;
    fs::create_directories(root / "surfaces", ec);
    const std::string name = rp::KneeStructureName(structure);
    const std::string path = (root / "surfaces" / (name + ".vtp")).string();
    if (!rp::WriteModelFile(path, surface, error)) return false;
    written.Surfaces[name] = path;
  }
  vtkNew<vtkMatrix4x4> mrToCT;
  vtkMatrix4x4::Invert(phantom.CTToMR, mrToCT);
  if (!rp::WriteTransformFile(written.TruthTransform, mrToCT, error)) return false;
  files = std::move(written);
  return true;
}

bool vtkRPVolumesLogic::ScanDicomFolder(const std::string& path, rp::DicomScanResult& scan, std::string& error,
                                        const rp::ProgressCallback& progress) {
  // DCMTK loads here, on the first scan (rpDicomEntries.h), not with the module.
  const auto scanDicom = rp::dicom::Entry<rp::dicom::ScanFunction>(rp::dicom::ScanEntry, path, error);
  return scanDicom && scanDicom(path, scan, error, progress);
}

rp::SceneConversion vtkRPVolumesLogic::ConvertScene(const std::string& in, const std::string& out) {
  return rp::ConvertScene(in, out);
}

rp::SegmentationConversion vtkRPVolumesLogic::ConvertSegmentation(const rp::SegmentationConversionRequest& request) {
  return rp::ConvertSegmentation(request);
}

bool vtkRPVolumesLogic::ConvertVolume(const std::string& in, const std::string& out,
                                      const rp::VolumeReadOptions& options, const std::string& modality,
                                      rp::ImageVolume& converted, std::vector<std::string>& warnings,
                                      std::string& error, const rp::ProgressCallback& progress) {
  rp::ImageVolume volume;
  if (!rp::ReadVolume(in, volume, error, options, &warnings, progress)) return false;
  rp::DicomWriteOptions dicom;
  dicom.Modality = !modality.empty() ? modality : (volume.Modality == "MR" ? "MR" : "CT");
  dicom.SeriesDescription = volume.Description;
  if (!rp::WriteVolume(out, volume, error, dicom, progress)) return false;
  converted = volume;
  return true;
}
