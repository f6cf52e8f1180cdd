#include "rpSegmentationToModels.h"

#include <vtkNew.h>
#include <vtkPolyData.h>

#include "vtkRPModelNode.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"

namespace rp {

namespace {
bool SameSurfaceOptions(const MeshOptions& a, const MeshOptions& b) {
  return a.Method == b.Method && a.Sigma == b.Sigma && a.GridStep[0] == b.GridStep[0] && a.GridStep[1] == b.GridStep[1] &&
         a.GridStep[2] == b.GridStep[2] && a.SincIterations == b.SincIterations && a.SincPassBand == b.SincPassBand &&
         a.DecimationFraction == b.DecimationFraction && a.CorrectVolume == b.CorrectVolume;
}
}  // namespace

std::vector<SegmentModels> BuildSegmentModels(vtkRPSegmentationNode* segmentation, const ModelBuildOptions& options,
                                              vtkRPScene* scene, const ProgressCallback& progress,
                                              const std::function<void(const SegmentModels&)>& done) {
  std::vector<SegmentModels> results;
  if (!segmentation) return results;
  std::vector<const vtkRPSegmentationNode::Segment*> segments;
  if (options.SegmentIDs.empty()) {
    for (const auto& s : segmentation->GetSegments()) segments.push_back(&s);
  } else {
    for (const auto& id : options.SegmentIDs) {
      const auto* s = segmentation->GetSegmentByID(id);
      if (!s) {
        SegmentModels missing;
        missing.SegmentID = id;
        missing.Error = "no segment '" + id + "' in the segmentation";
        results.push_back(missing);
        continue;
      }
      segments.push_back(s);
    }
  }
  const double parts = static_cast<double>(segments.size()) * (options.MakeHaptic ? 2 : 1);
  double finished = 0;
  for (const auto* s : segments) {
    SegmentModels r;
    r.SegmentID = s->ID;
    r.Name = s->Name.empty() ? s->ID : s->Name;
    r.TissueClass = s->TissueClass;
    auto stage = [&](const std::string& what) -> ProgressCallback {
      if (!progress) return nullptr;
      const double base = finished;
      return [&, base, what](double f, const std::string& message) {
        progress((base + f) / parts, r.Name + " " + what + ": " + message);
      };
    };
    auto makeModel = [&](vtkPolyData* mesh, bool haptic) {
      auto model = vtkSmartPointer<vtkRPModelNode>::New();
      model->SetName(haptic ? r.Name + " (haptic)" : r.Name);
      model->SetPolyData(mesh);
      model->SetColor(s->Color[0], s->Color[1], s->Color[2]);
      model->SetTissueClass(s->TissueClass);
      model->SetHaptic(haptic);
      model->SetVisibility(!haptic);
      if (scene) scene->AddNode(model);
      return model;
    };
    vtkNew<vtkPolyData> display;
    if (!LabelmapToMeshLOD(segmentation->GetImageData(), segmentation->GetIJKToRASMatrix(), s->LabelValue,
                           options.Display, options.DisplayLOD, display, r.Display, r.Error, stage("display"))) {
      r.Error = "segment '" + s->ID + "': " + r.Error;
      results.push_back(r);
      finished += options.MakeHaptic ? 2 : 1;
      continue;
    }
    finished += 1;
    r.DisplayModel = makeModel(display, false);
    if (done && options.MakeHaptic) done(r);
    if (options.MakeHaptic) {
      vtkNew<vtkPolyData> haptic;
      // The display mesh is the full-resolution surface when it has no target of its own and the
      // same options: the haptic level of detail starts from it instead of building it again.
      const bool displayIsFull = options.DisplayLOD.TargetTriangles <= 0 && options.DisplayLOD.MaxErrorMm <= 0 &&
                                 SameSurfaceOptions(options.Display, options.Haptic);
      if (!LabelmapToMeshLOD(segmentation->GetImageData(), segmentation->GetIJKToRASMatrix(), s->LabelValue,
                             options.Haptic, options.HapticLOD, haptic, r.Haptic, r.Error, stage("haptic"),
                             displayIsFull ? display.GetPointer() : nullptr, displayIsFull ? &r.Display : nullptr)) {
        r.Error = "segment '" + s->ID + "' (haptic mesh): " + r.Error;
        results.push_back(r);
        finished += 1;
        continue;
      }
      finished += 1;
      r.HapticModel = makeModel(haptic, true);
    }
    r.Ok = true;
    results.push_back(r);
    if (done) done(results.back());
  }
  return results;
}

}  // namespace rp
