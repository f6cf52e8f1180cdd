// The risk map picture of rpPlanPictures.h, drawn offscreen by VTK: in libRoboPlanPlanningPictures.so,
// which rp::WriteRiskMapPicture loads when a command draws one, so that `roboplan plan` and every
// module that links the planning logic map no VTK rendering until they draw.
#include <algorithm>

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkLineSource.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkTubeFilter.h>

#include "rpPlanPictures.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpWindowPicture.h"

namespace rp {
namespace {

// Red below 0 mm, through orange and yellow to green at `high` mm and beyond.
vtkSmartPointer<vtkLookupTable> ClearanceColours(double high) {
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  lut->SetTableRange(0, high);
  lut->SetHueRange(0.0, 0.33);
  lut->SetSaturationRange(0.9, 0.9);
  lut->SetValueRange(0.95, 0.85);
  lut->SetBelowRangeColor(0.6, 0, 0, 1);
  lut->UseBelowRangeColorOn();
  lut->Build();
  return lut;
}

vtkSmartPointer<vtkActor> LineActor(const Vec3& a, const double b[3], double radius, const double color[3]) {
  vtkNew<vtkLineSource> line;
  line->SetPoint1(a.x, a.y, a.z);
  line->SetPoint2(const_cast<double*>(b));
  vtkNew<vtkTubeFilter> tube;
  tube->SetInputConnection(line->GetOutputPort());
  tube->SetRadius(radius);
  tube->SetNumberOfSides(16);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(tube->GetOutputPort());
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(const_cast<double*>(color));
  return actor;
}

bool DrawRiskMapPicture(const std::string& path, vtkPolyData* riskMap, const std::vector<StructureAtRiskSnapshot>& structures,
                         const double target[3], const std::vector<Vec3>& candidates, const ProposalResult& result,
                         std::string& error) {
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(1, 1, 1);
  double best = 10;
  if (!result.Best.empty()) best = std::max(2.0, 1.5 * result.Scores[static_cast<size_t>(result.Best.front())].ClearanceMm);
  const auto lut = ClearanceColours(best);
  vtkNew<vtkPolyDataMapper> mapMapper;
  mapMapper->SetInputData(riskMap);
  mapMapper->SetLookupTable(lut);
  mapMapper->SetScalarRange(0, best);
  mapMapper->SetScalarModeToUsePointFieldData();
  mapMapper->SelectColorArray("clearanceMm");
  mapMapper->ScalarVisibilityOn();
  vtkNew<vtkActor> mapActor;
  mapActor->SetMapper(mapMapper);
  renderer->AddActor(mapActor);
  for (const auto& s : structures) {  // the structures at risk, translucent red
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(TriangleMeshToPolyData(*s.Surface));
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetColor(0.85, 0.2, 0.2);
    actor->GetProperty()->SetOpacity(0.45);
    renderer->AddActor(actor);
  }
  const double first[3] = {0.1, 0.3, 0.95}, other[3] = {0.55, 0.6, 0.9};
  for (size_t k = 0; k < result.Best.size(); ++k)
    renderer->AddActor(LineActor(candidates[static_cast<size_t>(result.Best[k])], target, k ? 0.5 : 0.9, k ? other : first));
  vtkNew<vtkScalarBarActor> bar;
  bar->SetLookupTable(lut);
  bar->SetTitle("clearance (mm)");
  bar->SetNumberOfLabels(5);
  bar->SetWidth(0.09);
  bar->SetHeight(0.6);
  bar->GetTitleTextProperty()->SetColor(0, 0, 0);
  bar->GetLabelTextProperty()->SetColor(0, 0, 0);
  renderer->AddActor2D(bar);
  vtkNew<vtkTextActor> title;
  title->SetInput("Risk map: entry region coloured by the tool's clearance; best trajectories blue, structures red");
  title->GetTextProperty()->SetColor(0, 0, 0);
  title->GetTextProperty()->SetFontSize(16);
  title->SetDisplayPosition(10, 10);
  renderer->AddActor2D(title);
  // Looking at the region from beyond it, away from the target.
  double bounds[6], c[3];
  riskMap->GetBounds(bounds);
  for (int i = 0; i < 3; ++i) c[i] = 0.5 * (bounds[2 * i] + bounds[2 * i + 1]);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetFocalPoint((c[0] + target[0]) / 2, (c[1] + target[1]) / 2, (c[2] + target[2]) / 2);
  camera->SetPosition(2 * c[0] - target[0], 2 * c[1] - target[1], 2 * c[2] - target[2]);
  camera->SetViewUp(0, 0, 1);
  renderer->ResetCamera();
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(900, 700);
  window->AddRenderer(renderer);
  return bench::WriteWindowPNG(window, path, error);
}

}  // namespace

}  // namespace rp

extern "C" __attribute__((visibility("default"))) bool roboplan_write_risk_map_picture(
    const std::string& path, vtkPolyData* riskMap, const std::vector<rp::StructureAtRiskSnapshot>& structures,
    const double target[3], const std::vector<rp::Vec3>& candidates, const rp::ProposalResult& result, std::string& error) {
  return rp::DrawRiskMapPicture(path, riskMap, structures, target, candidates, result, error);
}
