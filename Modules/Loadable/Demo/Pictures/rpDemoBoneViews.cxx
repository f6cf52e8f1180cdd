// The knee as a surgeon looks at it: the bone models alone, each in its colour, seen from the
// front (anterior) and from the side (lateral for the knee's side), side by side, the camera
// framed on the bones. Rendered offscreen with plain VTK (no slices, no soft tissue in the way).
// Part of libRoboPlanDemoPictures.so (rpDemoPictures.h).
#include <algorithm>
#include <cmath>

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCoordinate.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include "rpBenchmarkChart.h"
#include "rpDemoPictures.h"
#include "rpWindowPicture.h"
#include "rpXDisplay.h"
#include "vtkRPModelNode.h"
#include "vtkRPScene.h"

namespace rp {

namespace {

bool DrawBoneViews(const demo_pictures::BoneViews& picture, const std::string& path, std::string& error) {
  const std::vector<std::string>& modelIDs = picture.ModelIDs;
  std::vector<vtkRPModelNode*> models;
  double bounds[6] = {1e300, -1e300, 1e300, -1e300, 1e300, -1e300};
  for (const std::string& id : modelIDs) {
    auto* model = vtkRPModelNode::SafeDownCast(picture.Scene->GetNodeByID(id));
    if (!model || !model->GetPolyData() || model->GetPolyData()->GetNumberOfPoints() == 0) continue;
    models.push_back(model);
    double b[6];
    model->GetPolyData()->GetBounds(b);
    for (int a = 0; a < 3; ++a) bounds[2 * a] = std::min(bounds[2 * a], b[2 * a]), bounds[2 * a + 1] = std::max(bounds[2 * a + 1], b[2 * a + 1]);
  }
  if (models.empty()) {
    error = "no bone models to show";
    return false;
  }
  // Along the knee's own axes when known; otherwise the scanner's, lateral being the side the
  // fibula is on.
  double lateral[3] = {picture.Lateral[0], picture.Lateral[1], picture.Lateral[2]};
  const double* anterior = picture.Anterior.data();
  if (!picture.AxesKnown) {
    for (vtkRPModelNode* model : models)
      if (model->GetName().find("ibula") != std::string::npos) {
        double b[6];
        model->GetPolyData()->GetBounds(b);
        const double side = 0.5 * (b[0] + b[1]) >= 0.5 * (bounds[0] + bounds[1]) ? 1.0 : -1.0;
        for (double& l : lateral) l *= side;
      }
  }
  const int width = 1600, height = 1000;
  vtkNew<vtkRenderWindow> window;
  if (!PrepareOffscreenWindow(window, error)) return false;
  window->SetMultiSamples(8);
  window->SetSize(width, height);
  const double centre[3] = {0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), 0.5 * (bounds[4] + bounds[5])};
  struct Side {
    const char* Title;
    const double* Direction;  // from the centre towards the camera
  };
  const Side sides[2] = {{"anterior", anterior}, {"lateral", lateral}};
  // The bones' extent across the screen seen along `direction` (horizontal, perpendicular to it).
  auto across = [&](const double* direction) {
    const double h[2] = {-direction[1], direction[0]};
    double lo = 1e300, hi = -1e300;
    for (int corner = 0; corner < 4; ++corner) {
      const double x = bounds[corner & 1 ? 1 : 0], y = bounds[corner & 2 ? 3 : 2];
      lo = std::min(lo, x * h[0] + y * h[1]);
      hi = std::max(hi, x * h[0] + y * h[1]);
    }
    return hi - lo;
  };
  for (int v = 0; v < 2; ++v) {
    vtkNew<vtkRenderer> renderer;
    renderer->SetViewport(0.5 * v, 0, 0.5 * (v + 1), 1);
    renderer->GradientBackgroundOn();
    renderer->SetBackground(0.28, 0.30, 0.36);
    renderer->SetBackground2(0.62, 0.65, 0.72);
    for (vtkRPModelNode* model : models) {
      vtkNew<vtkPolyDataNormals> normals;
      normals->SetInputData(model->GetPolyData());
      normals->SplittingOff();
      vtkNew<vtkPolyDataMapper> mapper;
      mapper->SetInputConnection(normals->GetOutputPort());
      mapper->ScalarVisibilityOff();
      vtkNew<vtkActor> actor;
      actor->SetMapper(mapper);
      const auto c = model->GetColor();
      actor->GetProperty()->SetColor(c[0], c[1], c[2]);
      actor->GetProperty()->SetSpecular(0.25);
      actor->GetProperty()->SetSpecularPower(30);
      renderer->AddActor(actor);
    }
    // Frame the bones: the larger of their height and their width on screen fills 90 % of the
    // view at the camera's view angle.
    vtkCamera* camera = renderer->GetActiveCamera();
    const double aspect = 0.5 * width / height;
    const double fit = std::max(bounds[5] - bounds[4], across(sides[v].Direction) / aspect) / 0.9;
    const double distance = 0.5 * fit / std::tan(0.5 * camera->GetViewAngle() * M_PI / 180.0) +
                            0.5 * std::max(bounds[1] - bounds[0], bounds[3] - bounds[2]);
    camera->SetFocalPoint(centre);
    camera->SetPosition(centre[0] + distance * sides[v].Direction[0], centre[1] + distance * sides[v].Direction[1],
                        centre[2] + distance * sides[v].Direction[2]);
    camera->SetViewUp(0, 0, 1);
    renderer->ResetCameraClippingRange();
    vtkNew<vtkTextActor> title;
    title->SetInput(sides[v].Title);
    title->GetTextProperty()->SetFontSize(26);
    title->GetTextProperty()->SetColor(1, 1, 1);
    title->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    title->SetPosition(0.03, 0.94);
    renderer->AddActor2D(title);
    if (v == 0) {
      // The legend: each bone's name in its colour.
      int y = 20;
      for (auto it = models.rbegin(); it != models.rend(); ++it) {
        vtkNew<vtkTextActor> name;
        name->SetInput((*it)->GetName().c_str());
        const auto c = (*it)->GetColor();
        name->GetTextProperty()->SetColor(c[0], c[1], c[2]);
        name->GetTextProperty()->SetFontSize(24);
        name->GetTextProperty()->BoldOn();
        name->GetTextProperty()->ShadowOn();
        name->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
        name->SetPosition(0.03, y / double(height));
        renderer->AddActor2D(name);
        y += 32;
      }
    }
    window->AddRenderer(renderer);
  }
  return bench::WriteWindowPNG(window, path, error);
}

}  // namespace

}  // namespace rp

RP_DEMO_PICTURES_ENTRY bool roboplan_demo_bone_views(const rp::demo_pictures::BoneViews& picture,
                                                     const std::string& path, std::string& error) {
  return rp::DrawBoneViews(picture, path, error);
}
