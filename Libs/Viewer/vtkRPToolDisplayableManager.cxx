#include "vtkRPToolDisplayableManager.h"

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <vtkActor.h>
#include <vtkAppendPolyData.h>
#include <vtkArrowSource.h>
#include <vtkCylinderSource.h>
#include <vtkMath.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkSphereSource.h>
#include <vtkTransform.h>
#include <vtkTransformPolyDataFilter.h>

#include "rpView.h"
#include "vtkRPLinearTransformNode.h"
#include "vtkRPTrackedToolNode.h"

vtkStandardNewMacro(vtkRPToolDisplayableManager);

namespace {

std::vector<double> ParseNumbers(const std::string& text) {
  std::vector<double> values;
  std::string item;
  std::stringstream stream(text);
  while (std::getline(stream, item, ',')) {
    try {
      values.push_back(std::stod(item));
    } catch (...) {
      return {};
    }
  }
  return values;
}

double NumberAttribute(vtkRPNode* node, const char* key, double fallback) {
  std::vector<double> values = ParseNumbers(node->GetAttribute(key));
  return values.size() == 1 && std::isfinite(values[0]) && values[0] > 0 ? values[0] : fallback;
}

// The force shown: "Viewer.Force", else the haptic proxy's own "Force" attribute.
std::string ForceText(vtkRPNode* node) {
  return node->HasAttribute("Viewer.Force") ? node->GetAttribute("Viewer.Force") : node->GetAttribute("Force");
}

std::string GlyphKind(vtkRPNode* node) {
  std::string kind = node->GetAttribute("Viewer.Glyph");
  if (kind.empty() && vtkRPTrackedToolNode::SafeDownCast(node)) {
    // A tool node that carries a force is the haptic proxy (god object): a sphere at its centre.
    kind = node->HasAttribute("Force") ? "sphere" : "stylus";
  }
  return kind;
}

// Geometry of a glyph in the node's frame.
void BuildGlyph(vtkRPNode* node, const std::string& kind, vtkAppendPolyData* append) {
  append->RemoveAllInputs();
  if (kind == "stylus") {
    const double length = NumberAttribute(node, "Viewer.GlyphLength", 80.0);
    vtkNew<vtkSphereSource> tip;
    tip->SetRadius(1.5);
    tip->SetThetaResolution(16);
    tip->SetPhiResolution(12);
    vtkNew<vtkCylinderSource> shaft;  // along Y by default: rotate it onto +Z, base at the tip
    shaft->SetRadius(1.0);
    shaft->SetHeight(length);
    shaft->SetResolution(16);
    vtkNew<vtkTransform> place;
    place->Translate(0, 0, 0.5 * length);
    place->RotateX(90);
    vtkNew<vtkTransformPolyDataFilter> moved;
    moved->SetTransform(place);
    moved->SetInputConnection(shaft->GetOutputPort());
    append->AddInputConnection(tip->GetOutputPort());
    append->AddInputConnection(moved->GetOutputPort());
  } else if (kind == "sphere") {
    vtkNew<vtkSphereSource> sphere;
    sphere->SetRadius(NumberAttribute(node, "Viewer.GlyphRadius", 2.0));
    sphere->SetThetaResolution(20);
    sphere->SetPhiResolution(16);
    append->AddInputConnection(sphere->GetOutputPort());
  } else if (kind == "axes") {
    const double length = NumberAttribute(node, "Viewer.GlyphLength", 30.0);
    for (int axis = 0; axis < 3; ++axis) {
      vtkNew<vtkCylinderSource> rod;
      rod->SetRadius(0.6);
      rod->SetHeight(length);
      vtkNew<vtkTransform> place;
      const double half = 0.5 * length;
      place->Translate(axis == 0 ? half : 0, axis == 1 ? half : 0, axis == 2 ? half : 0);
      if (axis == 0) place->RotateZ(-90);
      if (axis == 2) place->RotateX(90);
      vtkNew<vtkTransformPolyDataFilter> moved;
      moved->SetTransform(place);
      moved->SetInputConnection(rod->GetOutputPort());
      append->AddInputConnection(moved->GetOutputPort());
    }
  }
}

}  // namespace

struct vtkRPToolDisplayableManager::Display {
  std::string Kind = "?";
  std::string GeometryKey;
  vtkNew<vtkAppendPolyData> Glyph;
  vtkNew<vtkPolyDataMapper> GlyphMapper;
  vtkNew<vtkActor> GlyphActor;
  vtkNew<vtkArrowSource> Arrow;
  vtkNew<vtkPolyDataMapper> ArrowMapper;
  vtkNew<vtkActor> ArrowActor;
  Display() {
    this->GlyphMapper->SetInputConnection(this->Glyph->GetOutputPort());
    this->GlyphActor->SetMapper(this->GlyphMapper);
    vtkNew<vtkMatrix4x4> glyphMatrix, arrowMatrix;
    this->GlyphActor->SetUserMatrix(glyphMatrix);
    this->GlyphActor->PickableOff();
    this->Arrow->SetShaftRadius(0.04);
    this->Arrow->SetTipRadius(0.12);
    this->Arrow->SetTipLength(0.25);
    this->ArrowMapper->SetInputConnection(this->Arrow->GetOutputPort());
    this->ArrowActor->SetMapper(this->ArrowMapper);
    this->ArrowActor->SetUserMatrix(arrowMatrix);
    this->ArrowActor->GetProperty()->SetColor(1.0, 0.85, 0.1);
    this->ArrowActor->PickableOff();
  }
};

vtkRPToolDisplayableManager::~vtkRPToolDisplayableManager() { this->Finalize(); }

bool vtkRPToolDisplayableManager::CanDisplay(vtkRPNode* node) const {
  // Every transform node is observed: a glyph attribute may be set later.
  return vtkRPLinearTransformNode::SafeDownCast(node) != nullptr;
}

vtkActor* vtkRPToolDisplayableManager::GetGlyphActor(vtkRPNode* node) const {
  auto it = this->Displays.find(node);
  return it == this->Displays.end() || !it->second->GlyphActor->GetVisibility() ? nullptr
                                                                                  : it->second->GlyphActor.GetPointer();
}

vtkActor* vtkRPToolDisplayableManager::GetForceActor(vtkRPNode* node) const {
  auto it = this->Displays.find(node);
  return it == this->Displays.end() || !it->second->ArrowActor->GetVisibility() ? nullptr
                                                                                  : it->second->ArrowActor.GetPointer();
}

void vtkRPToolDisplayableManager::AddDisplay(vtkRPNode* node) {
  auto display = std::make_unique<Display>();
  vtkRenderer* renderer = this->GetView()->GetOverlayRenderer();
  renderer->AddActor(display->GlyphActor);
  renderer->AddActor(display->ArrowActor);
  display->GlyphActor->SetVisibility(false);
  display->ArrowActor->SetVisibility(false);
  this->Displays[node] = std::move(display);
}

void vtkRPToolDisplayableManager::RemoveDisplay(vtkRPNode* node) {
  auto it = this->Displays.find(node);
  if (it == this->Displays.end()) return;
  if (this->GetView()) {
    vtkRenderer* renderer = this->GetView()->GetOverlayRenderer();
    renderer->RemoveActor(it->second->GlyphActor);
    renderer->RemoveActor(it->second->ArrowActor);
  }
  this->Displays.erase(it);
}

void vtkRPToolDisplayableManager::UpdateDisplay(vtkRPNode* node) {
  auto* transform = vtkRPLinearTransformNode::SafeDownCast(node);
  auto it = this->Displays.find(node);
  if (!transform || it == this->Displays.end()) return;
  Display& display = *it->second;

  const std::string kind = GlyphKind(node);
  const std::string geometryKey = kind + "|" + node->GetAttribute("Viewer.GlyphLength") + "|" +
                                  node->GetAttribute("Viewer.GlyphRadius");
  if (geometryKey != display.GeometryKey) {
    BuildGlyph(node, kind, display.Glyph);
    display.GeometryKey = geometryKey;
  }
  const bool hasGlyph = kind == "stylus" || kind == "sphere" || kind == "axes";
  vtkNew<vtkMatrix4x4> toWorld;
  transform->GetMatrixTransformToWorld(toWorld);
  display.GlyphActor->GetUserMatrix()->DeepCopy(toWorld);
  display.GlyphActor->SetVisibility(hasGlyph);

  double color[3] = {0.3, 0.9, 1.0};
  std::vector<double> rgb = ParseNumbers(node->GetAttribute("Viewer.Color"));
  if (rgb.size() == 3) {
    for (int i = 0; i < 3; ++i) color[i] = std::min(1.0, std::max(0.0, rgb[static_cast<size_t>(i)]));
  }
  double opacity = 1.0;
  if (auto* tool = vtkRPTrackedToolNode::SafeDownCast(node)) {
    // A pose the tracker does not vouch for is drawn faded grey-red: do not trust it.
    if (tool->GetStatus() != vtkRPTrackedToolNode::StatusOK && tool->GetStatus() != vtkRPTrackedToolNode::StatusUnknown) {
      color[0] = 0.8;
      color[1] = 0.35;
      color[2] = 0.35;
      opacity = 0.4;
    }
  }
  display.GlyphActor->GetProperty()->SetColor(color);
  display.GlyphActor->GetProperty()->SetOpacity(opacity);

  // Force arrow from the node's origin, in RAS.
  std::vector<double> force = ParseNumbers(ForceText(node));
  const double magnitude = force.size() == 3 ? std::sqrt(force[0] * force[0] + force[1] * force[1] + force[2] * force[2]) : 0.0;
  if (magnitude > 1e-9 && std::isfinite(magnitude)) {
    const double length = magnitude * NumberAttribute(node, "Viewer.ForceScale", 10.0);
    double x[3] = {force[0] / magnitude, force[1] / magnitude, force[2] / magnitude}, y[3], z[3];
    vtkMath::Perpendiculars(x, y, z, 0.0);
    const double thickness = std::min(length, 20.0);
    vtkMatrix4x4* m = display.ArrowActor->GetUserMatrix();
    m->Identity();
    for (int r = 0; r < 3; ++r) {
      m->SetElement(r, 0, x[r] * length);
      m->SetElement(r, 1, y[r] * thickness);
      m->SetElement(r, 2, z[r] * thickness);
      m->SetElement(r, 3, toWorld->GetElement(r, 3));
    }
    m->Modified();
    display.ArrowActor->SetVisibility(true);
  } else {
    display.ArrowActor->SetVisibility(false);
  }
  display.ArrowActor->Modified();
  display.GlyphActor->Modified();
}
