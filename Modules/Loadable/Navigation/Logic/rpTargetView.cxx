#include "rpTargetView.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkImageActor.h>
#include <vtkImageData.h>
#include <vtkImageMapToWindowLevelColors.h>
#include <vtkImageMapper3D.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRendererCollection.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>

#include "rpVolumeReslice.h"
#include "rpXDisplay.h"
#include "vtkRPScalarVolumeNode.h"

namespace rp {

namespace {

Vec3 TipOf(const GuidanceReadout& r) { return {r.ToolTipToTrajectory[3], r.ToolTipToTrajectory[7], r.ToolTipToTrajectory[11]}; }

// The tool's direction (its `forward` in its own frame) in the trajectory's frame.
Vec3 ForwardOf(const GuidanceReadout& r, const Vec3& f) {
  const double* m = r.ToolTipToTrajectory;
  return Normalized(Vec3{m[0] * f.x + m[1] * f.y + m[2] * f.z, m[4] * f.x + m[5] * f.y + m[6] * f.z,
                         m[8] * f.x + m[9] * f.y + m[10] * f.z});
}

// A slice at the tip's depth whose columns are the trajectory's axes given (±x, ±y, ±z).
void SliceAtTipDepth(const TrajectoryAxis& plan, const GuidanceReadout& r, const Vec3 (&columns)[3], vtkMatrix4x4* out) {
  double f[16];
  TrajectoryToRAS(plan, f);
  const Vec3 centre = plan.PointAt(TipOf(r).z);
  out->Identity();
  for (int c = 0; c < 3; ++c) {
    const Vec3& a = columns[c];  // in the trajectory's frame → RAS
    for (int row = 0; row < 3; ++row) out->SetElement(row, c, f[4 * row] * a.x + f[4 * row + 1] * a.y + f[4 * row + 2] * a.z);
  }
  out->SetElement(0, 3, centre.x);
  out->SetElement(1, 3, centre.y);
  out->SetElement(2, 3, centre.z);
}

// Lines and discs as one coloured, unlit actor (the picture's colours are exact).
struct Shapes {
  vtkNew<vtkPoints> Points;
  vtkNew<vtkCellArray> Lines, Polygons;
  void Polyline(const std::vector<Vec3>& p) {
    std::vector<vtkIdType> ids;
    for (const Vec3& q : p) ids.push_back(this->Points->InsertNextPoint(q.x, q.y, q.z));
    this->Lines->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
  }
  void Circle(double x, double y, double z, double radius, bool filled, int sides = 96) {
    std::vector<vtkIdType> ids;
    for (int i = 0; i < sides; ++i) {
      const double a = 2 * M_PI * i / sides;
      ids.push_back(this->Points->InsertNextPoint(x + radius * std::cos(a), y + radius * std::sin(a), z));
    }
    if (filled) {
      this->Polygons->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
    } else {
      ids.push_back(ids.front());
      this->Lines->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
    }
  }
  void Cross(double x, double y, double z, double half) {
    this->Polyline({{x - half, y, z}, {x + half, y, z}});
    this->Polyline({{x, y - half, z}, {x, y + half, z}});
  }
  vtkSmartPointer<vtkActor> Actor(const double colour[3], double width = 2) const {
    vtkNew<vtkPolyData> data;
    data->SetPoints(this->Points);
    data->SetLines(this->Lines);
    data->SetPolys(this->Polygons);
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(data);
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    actor->GetProperty()->SetColor(colour[0], colour[1], colour[2]);
    actor->GetProperty()->SetLighting(false);
    actor->GetProperty()->SetLineWidth(static_cast<float>(width));
    return actor;
  }
};

void Text(vtkRenderer* renderer, const std::string& text, double x, double y, int size = 13) {
  vtkNew<vtkTextActor> actor;
  actor->SetInput(text.c_str());
  actor->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  actor->SetPosition(x, y);
  actor->GetTextProperty()->SetFontSize(size);
  actor->GetTextProperty()->SetColor(0.95, 0.95, 0.95);
  actor->GetTextProperty()->SetBackgroundColor(0, 0, 0);  // readable over a bright slice
  actor->GetTextProperty()->SetBackgroundOpacity(0.6);
  renderer->AddActor2D(actor);
}

// A parallel camera on the plane z = 0 looking along `look` with `up`, `halfHeight` mm to the edge.
void Camera(vtkRenderer* renderer, double look, const double up[3], double halfHeight) {
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->ParallelProjectionOn();
  camera->SetFocalPoint(0, 0, 0);
  camera->SetPosition(0, 0, -100 * look);
  camera->SetViewUp(up[0], up[1], up[2]);
  camera->SetParallelScale(halfHeight);
  renderer->ResetCameraClippingRange(-200, 200, -200, 200, -200, 200);
}

const double Red[3] = {1.0, 0.25, 0.25}, Cyan[3] = {0.1, 0.85, 1.0}, Yellow[3] = {1.0, 0.9, 0.1}, Grey[3] = {0.6, 0.6, 0.65};

}  // namespace

TargetViewGeometry ComputeTargetViewGeometry(const GuidanceReadout& r, double planLengthMm, const Vec3& forward) {
  TargetViewGeometry g;
  if (!r.Valid) return g;
  g.Valid = true;
  const Vec3 tip = TipOf(r), d = ForwardOf(r, forward);
  g.Tip[0] = tip.x;
  g.Tip[1] = tip.y;
  g.Crosses = std::fabs(d.z) > 1e-6;
  if (g.Crosses) {
    const Vec3 atEntry = tip + d * ((0 - tip.z) / d.z), atTarget = tip + d * ((planLengthMm - tip.z) / d.z);
    g.EntryCrossing[0] = atEntry.x;
    g.EntryCrossing[1] = atEntry.y;
    g.TargetCrossing[0] = atTarget.x;
    g.TargetCrossing[1] = atTarget.y;
  }
  return g;
}

void AlongAxisSliceToRAS(const TrajectoryAxis& plan, const GuidanceReadout& r, vtkMatrix4x4* sliceToRAS) {
  const Vec3 columns[3] = {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}};  // x right, the entry up
  SliceAtTipDepth(plan, r, columns, sliceToRAS);
}

void AcrossAxisSliceToRAS(const TrajectoryAxis& plan, const GuidanceReadout& r, vtkMatrix4x4* sliceToRAS) {
  const Vec3 columns[3] = {{1, 0, 0}, {0, -1, 0}, {0, 0, -1}};  // as the target view: x right, −y up
  SliceAtTipDepth(plan, r, columns, sliceToRAS);
}

void TargetViewPicture::TargetViewToPixel(const double xy[2], double pixel[2]) const {
  const double scale = this->Opts.PaneSize / (2 * this->Opts.HalfWidthMm);
  pixel[0] = 0.5 * this->Opts.PaneSize + xy[0] * scale;
  pixel[1] = 0.5 * this->Opts.PaneSize - xy[1] * scale;  // the trajectory's −y is up
}

bool TargetViewPicture::Render(const TrajectoryAxis& plan, const GuidanceReadout& r, vtkRPScalarVolumeNode* volume,
                               std::string& error) {
  if (!r.Valid || !(plan.Length() > 0)) {
    error = "target view: no read-out (choose a tool and a complete trajectory)";
    return false;
  }
  if (!this->Window) {  // one window (one GL context) for every picture: the panel draws at display rate
    auto window = vtkSmartPointer<vtkRenderWindow>::New();
    if (!PrepareOffscreenWindow(window, error)) return false;
    this->Window = window;
  }
  vtkRenderWindow* window = this->Window;
  while (vtkRenderer* old = window->GetRenderers()->GetFirstRenderer()) window->RemoveRenderer(old);
  const int p = this->Opts.PaneSize;
  window->SetSize(3 * p, p);
  window->SetMultiSamples(0);  // exact colours: the test finds the tip by its colour
  const TargetViewGeometry g = ComputeTargetViewGeometry(r, plan.Length());
  const Vec3 tip = TipOf(r), d = ForwardOf(r, {0, 0, -1});
  const double upTarget[3] = {0, -1, 0}, upSlice[3] = {0, 1, 0};

  // The target view, in the trajectory's x, y (looking along its +z from the entry).
  vtkNew<vtkRenderer> target;
  target->SetViewport(0, 0, 1.0 / 3, 1);
  target->SetBackground(0.08, 0.09, 0.12);
  Shapes rings, centre, axis, entry, tipDot;
  for (double ring : this->Opts.RingsMm) rings.Circle(0, 0, 0, ring, false);
  centre.Cross(0, 0, -0.05, 0.6);
  if (g.Crosses) {
    axis.Polyline({{g.EntryCrossing[0], g.EntryCrossing[1], -0.1}, {g.TargetCrossing[0], g.TargetCrossing[1], -0.1}});
    axis.Cross(g.TargetCrossing[0], g.TargetCrossing[1], -0.1, 0.35);
    entry.Circle(g.EntryCrossing[0], g.EntryCrossing[1], -0.15, 0.35, false, 4);
  }
  tipDot.Circle(g.Tip[0], g.Tip[1], -0.2, 0.25, true, 32);
  target->AddActor(rings.Actor(Grey, 1));
  target->AddActor(centre.Actor(Red));
  target->AddActor(axis.Actor(Cyan));
  target->AddActor(entry.Actor(Yellow));
  target->AddActor(tipDot.Actor(TipColour));
  Camera(target, 1, upTarget, this->Opts.HalfWidthMm);
  char line[160];
  std::snprintf(line, sizeof line, "depth to target %.1f mm\nlateral %.1f mm  angle %.1f deg", r.DepthToTargetMm, r.LateralMm,
                r.AngleDeg);
  Text(target, line, 0.03, 0.03);
  std::snprintf(line, sizeof line, "target view  (rings %g, %g, %g mm)", this->Opts.RingsMm[0], this->Opts.RingsMm[1],
                this->Opts.RingsMm[2]);
  Text(target, line, 0.03, 0.92, 12);
  window->AddRenderer(target);

  // The re-sliced views: slice coordinates (u right, v up), the tip's depth at v = 0.
  for (int pane = 1; pane <= 2; ++pane) {
    const bool along = pane == 1;
    vtkNew<vtkRenderer> renderer;
    renderer->SetViewport(pane / 3.0, 0, (pane + 1) / 3.0, 1);
    renderer->SetBackground(0.05, 0.05, 0.06);
    // Trajectory coordinates → this slice's (u, v) (AlongAxisSliceToRAS / AcrossAxisSliceToRAS).
    auto uv = [&](const Vec3& t) { return along ? Vec3{t.x, -(t.z - tip.z), 0.2} : Vec3{t.x, -t.y, 0.2}; };
    if (volume && volume->GetImageData()) {
      vtkNew<vtkMatrix4x4> sliceToRAS;
      if (along) AlongAxisSliceToRAS(plan, r, sliceToRAS);
      else AcrossAxisSliceToRAS(plan, r, sliceToRAS);
      ResliceOptions options;
      options.FieldOfView[0] = options.FieldOfView[1] = this->Opts.SliceFieldMm;
      options.Spacing = this->Opts.SliceSpacingMm;
      double range[2];
      volume->GetImageData()->GetScalarRange(range);
      options.Background = range[0];
      vtkSmartPointer<vtkImageData> slice = ResliceVolume(volume, sliceToRAS, options);
      vtkNew<vtkImageMapToWindowLevelColors> grey;
      grey->SetInputData(slice);
      grey->SetWindow(std::max(1e-6, range[1] - range[0]));
      grey->SetLevel(0.5 * (range[0] + range[1]));
      grey->SetOutputFormatToRGB();
      grey->Update();
      vtkNew<vtkImageActor> image;
      image->GetMapper()->SetInputData(grey->GetOutput());
      renderer->AddActor(image);
    } else {
      Text(renderer, "no volume to re-slice", 0.2, 0.5);
    }
    Shapes plannedLine, tool, tipMark;
    if (along) {
      plannedLine.Polyline({uv({0, 0, 0}), uv({0, 0, plan.Length()})});
    } else {
      const Vec3 c = uv({0, 0, 0});
      plannedLine.Cross(c.x, c.y, c.z, 1.5);
    }
    const Vec3 shaft = tip - d * (this->Opts.SliceFieldMm * 0.4);
    tool.Polyline({uv(shaft), uv(tip)});
    const Vec3 t = uv(tip);
    tipMark.Circle(t.x, t.y, t.z + 0.1, 0.6, true, 24);
    renderer->AddActor(plannedLine.Actor(Red));
    if (along) renderer->AddActor(tool.Actor(Cyan));
    renderer->AddActor(tipMark.Actor(TipColour));
    Camera(renderer, -1, upSlice, 0.5 * this->Opts.SliceFieldMm);
    Text(renderer, along ? "along the plan (entry up)" : "across the plan at the tip", 0.03, 0.92, 12);
    window->AddRenderer(renderer);
  }
  window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  this->Image = vtkSmartPointer<vtkImageData>::New();
  this->Image->DeepCopy(grab->GetOutput());
  return true;
}

bool TargetViewPicture::WritePNG(const std::string& path, std::string& error) const {
  if (!this->Image) {
    error = "target view: nothing drawn yet";
    return false;
  }
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(this->Image);
  writer->Write();
  if (writer->GetErrorCode() != 0) {
    error = "cannot write " + path;
    return false;
  }
  return true;
}

}  // namespace rp
