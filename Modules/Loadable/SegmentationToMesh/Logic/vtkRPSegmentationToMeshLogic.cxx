#include "vtkRPSegmentationToMeshLogic.h"

#include <filesystem>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>

#include "rpImageVolume.h"
#include "rpVolumeIO.h"
#include "vtkRPModelNode.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"

namespace rp {

std::string SegmentMethod::Name() const {
  switch (this->Method) {
    case Threshold:
      return "threshold";
    case RegionGrow:
      return "region-grow";
    default:
      return "confidence";
  }
}

bool ParseSegmentMethod(const std::string& text, SegmentMethod::Kind& kind) {
  for (const auto k : {SegmentMethod::Threshold, SegmentMethod::RegionGrow, SegmentMethod::ConfidenceConnected}) {
    SegmentMethod method;
    method.Method = k;
    if (method.Name() == text) {
      kind = k;
      return true;
    }
  }
  return false;
}

std::string SegmentEdit::Name() const {
  static const char* const names[] = {"closing", "opening", "fill-holes", "keep-largest", "keep-at-seed", "split"};
  return names[this->Edit];
}

}  // namespace rp

vtkStandardNewMacro(vtkRPSegmentationToMeshLogic);

vtkRPSegmentationToMeshLogic::vtkRPSegmentationToMeshLogic() = default;

vtkRPSegmentationToMeshLogic::~vtkRPSegmentationToMeshLogic() = default;

void vtkRPSegmentationToMeshLogic::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Scene: " << this->Scene << "\n" << indent << "PreviewID: " << this->PreviewID << "\n";
}

void vtkRPSegmentationToMeshLogic::SetScene(vtkRPScene* scene) {
  if (scene == this->Scene) return;
  this->Scene = scene;
  this->PreviewID.clear();
  this->CreatedModelIDs.clear();
}

vtkRPNode* vtkRPSegmentationToMeshLogic::LoadInput(const std::string& path, const rp::ReadOptions& options,
                                                   std::vector<std::string>& warnings, std::string& error) {
  if (!this->Scene) {
    error = "the segmentation logic has no scene";
    return nullptr;
  }
  rp::LoadResult load;
  vtkRPNode* loaded = rp::LoadSingleNode(this->Scene, path, load, options);
  error = load.Error;
  warnings.insert(warnings.end(), load.Warnings.begin(), load.Warnings.end());
  if (!loaded && rp::HasExtension(path, ".seg.nrrd")) {
    // A plain labelmap named *.seg.nrrd (no Slicer segment keys): read it as a volume.
    vtkNew<vtkRPScalarVolumeNode> plain;
    std::string volumeError;
    if (rp::ReadVolumeFile(path, plain, volumeError)) {
      plain->SetName(std::filesystem::path(path).filename().string());
      this->Scene->AddNode(plain);
      loaded = plain;
    }
  }
  return loaded;
}

vtkRPSegmentationNode* vtkRPSegmentationToMeshLogic::AddSegmentation(const std::string& name) {
  if (!this->Scene) return nullptr;
  vtkNew<vtkRPSegmentationNode> segmentation;
  segmentation->SetName(name);
  this->Scene->AddNode(segmentation);
  return segmentation;
}

vtkRPSegmentationNode* vtkRPSegmentationToMeshLogic::SegmentationFromLabelmap(vtkRPScalarVolumeNode* volume,
                                                                               const rp::LabelTable* table,
                                                                               const std::string& name,
                                                                               bool copyVoxels, std::string& error,
                                                                               const rp::ImageValues* known) {
  if (!this->Scene || !volume || !volume->GetImageData()) {
    error = "pick an input volume";
    return nullptr;
  }
  vtkNew<vtkRPSegmentationNode> segmentation;
  segmentation->SetName(name);
  vtkSmartPointer<vtkImageData> labels = volume->GetImageData();
  if (copyVoxels) {
    labels = vtkSmartPointer<vtkImageData>::New();
    labels->DeepCopy(volume->GetImageData());
  }
  if (!rp::LabelmapToSegmentation(labels, volume->GetIJKToRASMatrix(), table, segmentation, error, known))
    return nullptr;
  this->Scene->AddNode(segmentation);
  return segmentation;
}

vtkRPSegmentationNode* vtkRPSegmentationToMeshLogic::SplitBones(vtkRPScalarVolumeNode* ct,
                                                                const rp::BoneSplitOptions& options,
                                                                const std::string& name, rp::BoneSplitResult& result,
                                                                std::string& error,
                                                                const rp::ProgressCallback& progress) {
  if (!this->Scene || !ct || !ct->GetImageData()) {
    error = "pick an input volume (a CT)";
    return nullptr;
  }
  vtkNew<vtkRPSegmentationNode> segmentation;
  segmentation->SetName(name);
  if (!rp::SplitBones(ct, segmentation, options, result, error, progress)) return nullptr;
  this->Scene->AddNode(segmentation);
  return segmentation;
}

bool vtkRPSegmentationToMeshLogic::RunMethod(vtkRPScalarVolumeNode* volume, vtkRPSegmentationNode* segmentation,
                                             const rp::SegmentTarget& target, const rp::SegmentMethod& method,
                                             rp::EditResult& result, std::string& error) {
  using Editor = rp::SegmentationEditor;
  switch (method.Method) {
    case rp::SegmentMethod::Threshold:
      return Editor::Threshold(volume, segmentation, target, method.Lower, method.Upper, result, error);
    case rp::SegmentMethod::RegionGrow:
      return Editor::RegionGrow(volume, segmentation, target, method.Seeds, method.Lower, method.Upper, result, error);
    default:
      return Editor::ConfidenceConnected(volume, segmentation, target, method.Seeds, method.Multiplier,
                                         method.Iterations, method.Radius, result, error);
  }
}

bool vtkRPSegmentationToMeshLogic::SegmentTissue(vtkRPScalarVolumeNode* volume, vtkRPSegmentationNode* segmentation,
                                                 const rp::TissueRecipe& recipe, std::vector<rp::TissueStep>& steps,
                                                 std::string& error) {
  if (!volume || !segmentation) {
    error = "segmenting needs an input volume and a segmentation";
    return false;
  }
  rp::TissueStep step{recipe.Target.ID, recipe.Method.Name(), false, {}};
  step.Ok = this->RunMethod(volume, segmentation, recipe.Target, recipe.Method, step.Result, error);
  steps.push_back(step);
  for (size_t i = 0; step.Ok && i < recipe.Edits.size(); ++i) {
    step = {recipe.Target.ID, recipe.Edits[i].Name(), false, steps.back().Result};
    step.Ok = this->EditSegment(segmentation, recipe.Target.ID, recipe.Edits[i], step.Result, error);
    steps.push_back(step);
  }
  return step.Ok;
}

bool vtkRPSegmentationToMeshLogic::EditSegment(vtkRPSegmentationNode* segmentation, const std::string& segmentID,
                                               const rp::SegmentEdit& edit, rp::EditResult& result,
                                               std::string& error) {
  using Editor = rp::SegmentationEditor;
  switch (edit.Edit) {
    case rp::SegmentEdit::Closing:
      return Editor::ApplyMorphology(segmentation, segmentID, rp::Morphology::Closing, edit.RadiusMm, result, error);
    case rp::SegmentEdit::Opening:
      return Editor::ApplyMorphology(segmentation, segmentID, rp::Morphology::Opening, edit.RadiusMm, result, error);
    case rp::SegmentEdit::FillHoles:
      return Editor::ApplyMorphology(segmentation, segmentID, rp::Morphology::FillHoles, 0, result, error);
    case rp::SegmentEdit::KeepLargest:
      return Editor::KeepLargestComponent(segmentation, segmentID, result, error);
    case rp::SegmentEdit::KeepAtSeed:
      return Editor::KeepComponentAtSeed(segmentation, segmentID, edit.Seed, result, error);
    default:
      return Editor::SplitComponents(segmentation, segmentID, edit.MaxSegments, 1, result, error);
  }
}

std::vector<rp::SegmentModels> vtkRPSegmentationToMeshLogic::CreateModels(
    vtkRPSegmentationNode* segmentation, const rp::ModelBuildOptions& options, const rp::ProgressCallback& progress,
    const std::function<void(const rp::SegmentModels&)>& built) {
  std::vector<rp::SegmentModels> models = rp::BuildSegmentModels(segmentation, options, nullptr, progress, built);
  if (!this->Scene || !segmentation) return models;
  // Built first, then swapped in: a segment that failed keeps its previous models.
  auto& created = this->CreatedModelIDs[segmentation->GetID()];
  bool meshed = false;
  this->Scene->StartBatchProcess();
  for (const rp::SegmentModels& m : models) {
    if (!m.Ok) continue;
    meshed = true;
    for (const std::string& oldID : created[m.SegmentID])
      if (vtkRPNode* old = this->Scene->GetNodeByID(oldID)) this->Scene->RemoveNode(old);
    auto& ids = created[m.SegmentID];
    ids.clear();
    for (vtkRPModelNode* model : {m.DisplayModel.Get(), m.HapticModel.Get()}) {
      if (!model) continue;
      this->Scene->AddNode(model);
      ids.push_back(model->GetID());
    }
  }
  if (meshed) this->RemovePreview();
  this->Scene->EndBatchProcess();
  return models;
}

bool vtkRPSegmentationToMeshLogic::PreviewSegment(vtkRPSegmentationNode* segmentation, const std::string& segmentID,
                                                  const rp::ModelBuildOptions& options, rp::MeshStats& stats,
                                                  std::string& error, const rp::ProgressCallback& progress) {
  const auto* segment = segmentation ? segmentation->GetSegmentByID(segmentID) : nullptr;
  if (!this->Scene || !segment) {
    error = "no segment selected (segment a tissue first)";
    return false;
  }
  vtkNew<vtkPolyData> mesh;
  if (!rp::LabelmapToMeshLOD(segmentation->GetImageData(), segmentation->GetIJKToRASMatrix(), segment->LabelValue,
                             options.Display, options.DisplayLOD, mesh, stats, error, progress))
    return false;
  // Replace the previous preview (whatever segment it showed) rather than piling up models.
  auto* model = vtkRPModelNode::SafeDownCast(this->Scene->GetNodeByID(this->PreviewID));
  vtkSmartPointer<vtkRPModelNode> created;
  if (!model) {
    created = vtkSmartPointer<vtkRPModelNode>::New();
    model = created;
  }
  const int previous = model->StartModify();
  model->SetName((segment->Name.empty() ? segment->ID : segment->Name) + " (preview)");
  model->SetPolyData(mesh);
  model->SetColor(segment->Color[0], segment->Color[1], segment->Color[2]);
  model->SetHaptic(false);  // no tissue class either: haptics never touch a preview
  model->SetVisibility(true);
  model->EndModify(previous);
  if (created) {
    this->Scene->AddNode(created);
    this->PreviewID = created->GetID();
  }
  return true;
}

void vtkRPSegmentationToMeshLogic::RemovePreview() {
  if (this->PreviewID.empty() || !this->Scene) return;
  vtkRPNode* node = this->Scene->GetNodeByID(this->PreviewID);
  this->PreviewID.clear();
  if (node) this->Scene->RemoveNode(node);
}

std::string vtkRPSegmentationToMeshLogic::GetPreviewNodeID() const {
  return this->Scene && this->Scene->GetNodeByID(this->PreviewID) ? this->PreviewID : std::string();
}

bool vtkRPSegmentationToMeshLogic::CompareWithTruth(vtkRPSegmentationNode* segmentation, const std::string& truthPath,
                                                    rp::LabelComparison& comparison, std::string& error) {
  if (!segmentation) {
    error = "no segmentation to score";
    return false;
  }
  vtkNew<vtkRPScalarVolumeNode> truth;
  std::vector<int> labels;
  for (const auto& s : segmentation->GetSegments()) labels.push_back(s.LabelValue);
  return rp::ReadVolumeFile(truthPath, truth, error) &&
         rp::CompareLabels(rp::FromNode(segmentation), rp::FromNode(truth), labels, comparison, error);
}
