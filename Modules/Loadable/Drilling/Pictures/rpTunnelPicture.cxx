// The tunnel picture of rpTunnelPicture.h, drawn offscreen by VTK: in libRoboPlanDrillingPictures.so,
// which rp::WriteTunnelPicture (Logic/rpTunnelPicture.cxx) loads when a command draws one.
#include "rpTunnelPicture.h"

#include <algorithm>

#include <cmath>

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkImageActor.h>
#include <vtkImageData.h>
#include <vtkImageMapper3D.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyLine.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkTubeFilter.h>

#include "rpBenchmarkChart.h"
#include "rpWindowPicture.h"
#include "rpDrillVolume.h"
#include "rpXDisplay.h"

namespace rp {

namespace {

// Bone colour per material code (1 + index): cortical ivory, trabecular tan, others grey.
vtkSmartPointer<vtkLookupTable> MaterialColours(const std::vector<Material>& materials) {
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  const int n = static_cast<int>(materials.size()) + 1;
  lut->SetNumberOfTableValues(n);
  lut->SetTableRange(0, n - 1);
  lut->SetTableValue(0, 0.8, 0.8, 0.8, 1);
  for (int m = 1; m < n; ++m) {
    const std::string& t = materials[size_t(m - 1)].Tissue;
    if (t == "bone")
      lut->SetTableValue(m, 0.95, 0.93, 0.84, 1);
    else if (t.find("trabecular") != std::string::npos)
      lut->SetTableValue(m, 0.86, 0.66, 0.42, 1);
    else
      lut->SetTableValue(m, 0.7, 0.7, 0.75, 1);
  }
  lut->Build();
  return lut;
}

vtkSmartPointer<vtkActor> Tube(const std::vector<Vec3>& points, double radius, const double color[3], double opacity = 1) {
  vtkNew<vtkPoints> pts;
  for (const Vec3& p : points) pts->InsertNextPoint(p.x, p.y, p.z);
  vtkNew<vtkPolyLine> line;
  line->GetPointIds()->SetNumberOfIds(pts->GetNumberOfPoints());
  for (vtkIdType i = 0; i < pts->GetNumberOfPoints(); ++i) line->GetPointIds()->SetId(i, i);
  vtkNew<vtkCellArray> lines;
  lines->InsertNextCell(line);
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(pts);
  poly->SetLines(lines);
  vtkNew<vtkTubeFilter> tube;
  tube->SetInputData(poly);
  tube->SetRadius(radius);
  tube->SetNumberOfSides(12);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(tube->GetOutputPort());
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(color[0], color[1], color[2]);
  actor->GetProperty()->SetOpacity(opacity);
  return actor;
}

vtkSmartPointer<vtkActor> BoneActor(vtkPolyData* bone, vtkLookupTable* lut, double opacity) {
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(bone);
  mapper->SetScalarModeToUsePointFieldData();
  mapper->SelectColorArray("Material");
  mapper->SetLookupTable(lut);
  mapper->SetColorModeToMapScalars();  // an unsigned char array would otherwise be read as colours
  mapper->SetScalarRange(lut->GetTableRange());
  mapper->ScalarVisibilityOn();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetOpacity(opacity);
  actor->GetProperty()->SetSpecular(0.15);
  return actor;
}

const double Background[3] = {0.12, 0.13, 0.16};
const double Removed[3] = {0.30, 0.55, 0.95};
const double ProtectedColour[3] = {0.9, 0.15, 0.15};

void MaterialColour(const std::vector<Material>& materials, int code, double rgb[3]) {
  const std::string tissue = code > 0 && size_t(code) <= materials.size() ? materials[size_t(code - 1)].Tissue : "";
  if (tissue == "bone") {
    rgb[0] = 0.95, rgb[1] = 0.93, rgb[2] = 0.84;
  } else if (tissue.find("trabecular") != std::string::npos) {
    rgb[0] = 0.86, rgb[1] = 0.66, rgb[2] = 0.42;
  } else {
    rgb[0] = rgb[1] = rgb[2] = 0.7;
  }
}

// The section through the axis as an RGB image: u (columns) across the tunnel, v (rows) along it
// from below the end of the stroke (v = 0) up to above its start.
vtkSmartPointer<vtkImageData> Section(const TunnelPicture& picture, const Vec3& axis, const Vec3& across, double& pixel,
                                      Vec3& origin, int size[2]) {
  const DrillVolume& volume = *picture.Volume;
  const double h = volume.Spacing();
  const double length = Norm(picture.To - picture.From);
  const double halfWidth = std::max(4 * picture.Radius, 10.0);
  pixel = std::max(h / 3, 0.05);
  while ((2 * halfWidth / pixel) * ((length + 2 * halfWidth) / pixel) > 4e6) pixel *= 1.25;
  size[0] = static_cast<int>(std::ceil(2 * halfWidth / pixel));
  size[1] = static_cast<int>(std::ceil((length + 2 * halfWidth) / pixel));
  const Vec3 along = -axis;
  origin = picture.To - along * halfWidth - across * halfWidth;  // pixel (0, 0)
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(size[0], size[1], 1);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* rgb = static_cast<unsigned char*>(image->GetScalarPointer());
  const DrillGrid& grid = volume.Grid();
  for (int v = 0; v < size[1]; ++v)
    for (int u = 0; u < size[0]; ++u) {
      const Vec3 p = origin + across * ((u + 0.5) * pixel) + along * ((v + 0.5) * pixel);
      const Vec3 x = grid.ToIndex(p);
      // Trilinear densities (now and as built); material of the nearest voxel.
      const int i = int(std::floor(x.x)), j = int(std::floor(x.y)), k = int(std::floor(x.z));
      double now = 0, built = 0;
      for (int c = 0; c < 8; ++c) {
        const int di = c & 1, dj = (c >> 1) & 1, dk = c >> 2;
        const double w = (di ? x.x - i : 1 - (x.x - i)) * (dj ? x.y - j : 1 - (x.y - j)) * (dk ? x.z - k : 1 - (x.z - k));
        now += w * volume.Density(i + di, j + dj, k + dk) / 255.0;
        built += w * volume.OriginalDensity(i + di, j + dj, k + dk) / 255.0;
      }
      const uint8_t code = volume.MaterialCode(int(std::lround(x.x)), int(std::lround(x.y)), int(std::lround(x.z)));
      double bone[3];
      MaterialColour(picture.Materials, code & DrillVolume::MaterialMask, bone);
      const double removed = std::max(0.0, built - now);
      double colour[3];
      for (int c = 0; c < 3; ++c) colour[c] = Background[c] * (1 - now - removed) + bone[c] * now + Removed[c] * removed;
      if (code & DrillVolume::ProtectedBit)
        for (int c = 0; c < 3; ++c) colour[c] = 0.45 * colour[c] + 0.55 * ProtectedColour[c];
      unsigned char* out = rgb + 3 * (size_t(v) * size[0] + u);
      for (int c = 0; c < 3; ++c) out[c] = static_cast<unsigned char>(std::clamp(colour[c], 0.0, 1.0) * 255 + 0.5);
    }
  // The planned tunnel (axis and walls, caps) in green, the burr's centre path in yellow.
  auto put = [&](double uu, double vv, const unsigned char c[3]) {
    const int u = int(std::floor(uu / pixel)), v = int(std::floor(vv / pixel));
    if (u < 0 || v < 0 || u >= size[0] || v >= size[1]) return;
    unsigned char* out = rgb + 3 * (size_t(v) * size[0] + u);
    out[0] = c[0], out[1] = c[1], out[2] = c[2];
  };
  const unsigned char green[3] = {60, 200, 80}, yellow[3] = {250, 200, 30};
  for (double s = 0; s <= length; s += pixel / 2) {
    put(halfWidth, halfWidth + s, green);
    put(halfWidth - picture.Radius, halfWidth + s, green);
    put(halfWidth + picture.Radius, halfWidth + s, green);
  }
  for (double a = 0; a <= M_PI; a += pixel / (2 * picture.Radius)) {
    put(halfWidth + picture.Radius * std::cos(a), halfWidth + length + picture.Radius * std::sin(a), green);
    put(halfWidth + picture.Radius * std::cos(a), halfWidth - picture.Radius * std::sin(a), green);
  }
  for (size_t i = 0; i < picture.Path.size(); i += std::max<size_t>(1, picture.Path.size() / 2000)) {
    const Vec3 d = picture.Path[i] - origin;
    put(Dot(d, across), Dot(d, along), yellow);
  }
  return image;
}

bool DrawTunnelPicture(const std::string& path, const TunnelPicture& picture, std::string& error) {
  if (!picture.Bone || picture.Bone->GetNumberOfPoints() == 0) {
    error = "tunnel picture: no bone mesh";
    return false;
  }
  if (Norm(picture.To - picture.From) < 1e-3) {
    error = "tunnel picture: the stroke has no length";
    return false;
  }
  const Vec3 axis = Normalized(picture.To - picture.From);
  const Vec3 mid = (picture.From + picture.To) * 0.5;
  const double length = std::max(Norm(picture.To - picture.From), 1e-3);
  // The cut plane contains the axis; the camera looks at it along its normal. Prefer a normal
  // close to anterior (a lateral-like section) unless the axis is itself near anterior.
  Vec3 reference = std::fabs(axis.y) < 0.8 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
  Vec3 normal = Normalized(reference - axis * Dot(reference, axis));
  if (Norm2(normal) == 0) normal = {1, 0, 0};
  const Vec3 up = -axis;  // the entrance at the top, the tunnel going down

  vtkNew<vtkRenderWindow> window;
  if (!PrepareOffscreenWindow(window, error)) return false;
  window->SetSize(picture.Width, picture.Height);
  auto lut = MaterialColours(picture.Materials);
  const double planned[3] = {0.2, 0.75, 0.25}, burr[3] = {0.95, 0.75, 0.1}, red[3] = {0.85, 0.15, 0.15};
  const double view = length + 4 * picture.Radius + 10;

  for (int side = 0; side < 2; ++side) {
    vtkNew<vtkRenderer> renderer;
    renderer->SetViewport(side * 0.5, 0, side * 0.5 + 0.5, 1);
    renderer->SetBackground(side ? 0.12 : 0.16, side ? 0.13 : 0.17, side ? 0.16 : 0.2);
    if (side == 1 && picture.Volume) {
      // The section, shown flat: image columns across the tunnel, rows along it.
      double pixel;
      Vec3 origin;
      int size[2];
      vtkSmartPointer<vtkImageData> section = Section(picture, axis, Cross(axis, normal), pixel, origin, size);
      section->SetSpacing(pixel, pixel, 1);
      vtkNew<vtkImageActor> image;
      image->GetMapper()->SetInputData(section);
      image->InterpolateOff();
      renderer->AddActor(image);
      renderer->SetBackground(Background[0], Background[1], Background[2]);
      vtkCamera* camera = renderer->GetActiveCamera();
      camera->ParallelProjectionOn();
      const double w = size[0] * pixel, hgt = size[1] * pixel;
      camera->SetFocalPoint(w / 2, hgt / 2, 0);
      camera->SetPosition(w / 2, hgt / 2, 100);
      camera->SetViewUp(0, 1, 0);
      const double aspect = 0.5 * picture.Width / double(picture.Height);
      camera->SetParallelScale(0.52 * std::max(hgt, w / aspect));
      renderer->ResetCameraClippingRange();
    } else {
      renderer->AddActor(BoneActor(picture.Bone, lut, 0.35));
      renderer->AddActor(Tube({picture.From, picture.To}, 0.12, planned));
      if (picture.Path.size() >= 2) {
        std::vector<Vec3> path;
        for (size_t i = 0; i < picture.Path.size(); i += std::max<size_t>(1, picture.Path.size() / 400)) path.push_back(picture.Path[i]);
        path.push_back(picture.Path.back());
        renderer->AddActor(Tube(path, 0.3, burr, 0.45));
      }
      if (picture.Protected && picture.Protected->GetNumberOfPoints() > 0) {
        vtkNew<vtkPolyDataMapper> mapper;
        mapper->SetInputData(picture.Protected);
        vtkNew<vtkActor> actor;
        actor->SetMapper(mapper);
        actor->GetProperty()->SetColor(red[0], red[1], red[2]);
        actor->GetProperty()->SetOpacity(0.5);
        renderer->AddActor(actor);
      }
      vtkCamera* camera = renderer->GetActiveCamera();
      camera->SetFocalPoint(mid.x, mid.y, mid.z);
      const Vec3 eye = mid + Normalized(normal + Cross(axis, normal) * 0.8) * (3 * view);
      camera->SetPosition(eye.x, eye.y, eye.z);
      camera->SetViewUp(up.x, up.y, up.z);
      camera->SetViewAngle(30);
      renderer->ResetCameraClippingRange();
    }
    vtkNew<vtkTextActor> label;
    label->SetInput(side ? "section through the axis: cortical ivory, trabecular tan,\n"
                           "drilled blue, protected red; planned tunnel green, burr centre yellow"
                         : "drilled bone, see-through:\nplanned axis green, burr centre path yellow");
    label->GetTextProperty()->SetFontSize(17);
    label->GetTextProperty()->SetColor(1, 1, 1);
    label->GetTextProperty()->SetBackgroundColor(0, 0, 0);
    label->GetTextProperty()->SetBackgroundOpacity(0.55);
    label->SetDisplayPosition(side * picture.Width / 2 + 12, 12);  // window coordinates
    renderer->AddActor2D(label);
    if (side == 0 && !picture.Title.empty()) {
      vtkNew<vtkTextActor> title;
      title->SetInput(picture.Title.c_str());
      title->GetTextProperty()->SetFontSize(20);
      title->GetTextProperty()->SetColor(1, 1, 1);
      title->SetDisplayPosition(12, picture.Height - 34);
      renderer->AddActor2D(title);
    }
    window->AddRenderer(renderer);
  }
  if (!bench::WriteWindowPNG(window, path, error)) {
    error = "tunnel picture: " + error;
    return false;
  }
  return true;
}

}  // namespace

}  // namespace rp

extern "C" __attribute__((visibility("default"))) bool roboplan_write_tunnel_picture(const std::string& path,
                                                                                    const rp::TunnelPicture& picture,
                                                                                    std::string& error) {
  return rp::DrawTunnelPicture(path, picture, error);
}
