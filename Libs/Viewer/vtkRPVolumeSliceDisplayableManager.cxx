#include "vtkRPVolumeSliceDisplayableManager.h"

#include <vtkActor.h>
#include <vtkCallbackCommand.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOpenGLShaderProperty.h>
#include <vtkPolyDataMapper.h>
#include <vtkPlaneSource.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkShader.h>
#include <vtkTexture.h>

#include "rpView.h"
#include "vtkRPSliceLogic.h"
#include "vtkRPSliceNode.h"

vtkStandardNewMacro(vtkRPVolumeSliceDisplayableManager);

// One slice node's picture in this view: a quad in plane coordinates, placed by the plane's
// matrix, textured with the RGBA picture as it is (no copy: the slice views used to draw the
// colours through an image actor, which copied and converted the picture twice per frame).
struct vtkRPVolumeSliceDisplayableManager::Picture {
  vtkRPSliceLogic* Logic = nullptr;
  unsigned long Tag = 0;
  vtkNew<vtkPlaneSource> Quad;
  vtkNew<vtkPolyDataMapper> QuadMapper;
  vtkNew<vtkTexture> Texture;
  vtkNew<vtkActor> QuadActor;
};

vtkRPVolumeSliceDisplayableManager::vtkRPVolumeSliceDisplayableManager() {
  this->LogicCallback = vtkSmartPointer<vtkCallbackCommand>::New();
  this->LogicCallback->SetClientData(this);
  this->LogicCallback->SetCallback(&vtkRPVolumeSliceDisplayableManager::OnLogicModified);
}

vtkRPVolumeSliceDisplayableManager::~vtkRPVolumeSliceDisplayableManager() { this->Finalize(); }

void vtkRPVolumeSliceDisplayableManager::OnInitialize() {
  rp::View* view = this->GetView();
  std::vector<vtkRPSliceLogic*> logics;
  if (view->IsSlice()) {
    logics.push_back(view->GetSliceLogic());
  } else {
    for (vtkRPSliceLogic* logic : view->GetSliceViewNodes().Logics) logics.push_back(logic);
  }
  for (vtkRPSliceLogic* logic : logics) {
    auto* picture = new Picture;
    picture->Logic = logic;
    if (logic) picture->Tag = logic->AddObserver(vtkCommand::ModifiedEvent, this->LogicCallback);
    if (logic) picture->Texture->SetInputConnection(logic->GetOutputPort());
    picture->Texture->InterpolateOn();
    picture->Texture->SetColorModeToDirectScalars();
    picture->QuadMapper->SetInputConnection(picture->Quad->GetOutputPort());
    // Slice views show the colours on black (the alpha, the patient mask, is ignored). In 3D the
    // air is cut away rather than blended: discarded fragments write no depth, so the three
    // planes and the models behind them are drawn correctly without sorting or peeling.
    vtkOpenGLShaderProperty::SafeDownCast(picture->QuadActor->GetShaderProperty())
        ->AddShaderReplacement(vtkShader::Fragment, "//VTK::TCoord::Impl", true,
                               view->IsSlice() ? "//VTK::TCoord::Impl\n  gl_FragData[0].a = 1.0;\n"
                                               : "//VTK::TCoord::Impl\n  if (gl_FragData[0].a < 0.5) { discard; }\n",
                               false);
    picture->QuadActor->SetMapper(picture->QuadMapper);
    picture->QuadActor->SetTexture(picture->Texture);
    picture->QuadActor->ForceOpaqueOn();
    picture->QuadActor->GetProperty()->LightingOff();
    picture->QuadActor->GetProperty()->SetAmbient(1.0);
    picture->QuadActor->GetProperty()->SetDiffuse(0.0);
    if (view->IsSlice()) picture->QuadActor->PickableOff();
    if (logic) picture->QuadActor->SetUserMatrix(logic->GetPlaneToRAS());
    // A slice view's image is its layer 0; in 3D the slices move with the slice point, so they
    // are drawn with what moves (layer 1), over the models' kept picture.
    this->LayerOf(view)->AddViewProp(picture->QuadActor);
    this->Pictures.push_back(picture);
    this->UpdatePicture(*picture);
  }
}

vtkRenderer* vtkRPVolumeSliceDisplayableManager::LayerOf(rp::View* view) {
  return view->IsSlice() ? view->GetRenderer() : view->GetOverlayRenderer();
}

void vtkRPVolumeSliceDisplayableManager::OnFinalize() {
  rp::View* view = this->GetView();
  for (Picture* picture : this->Pictures) {
    if (picture->Logic) picture->Logic->RemoveObserver(picture->Tag);
    if (view) this->LayerOf(view)->RemoveViewProp(picture->QuadActor);
    delete picture;
  }
  this->Pictures.clear();
}

vtkActor* vtkRPVolumeSliceDisplayableManager::GetSliceActor(int i) const {
  if (i < 0 || i >= static_cast<int>(this->Pictures.size())) return nullptr;
  return this->Pictures[static_cast<size_t>(i)]->QuadActor;
}

int vtkRPVolumeSliceDisplayableManager::GetNumberOfVisibleSlices() const {
  int visible = 0;
  for (Picture* picture : this->Pictures) visible += picture->QuadActor->GetVisibility() ? 1 : 0;
  return visible;
}

void vtkRPVolumeSliceDisplayableManager::OnLogicModified(vtkObject* caller, unsigned long, void* clientData, void*) {
  auto* self = static_cast<vtkRPVolumeSliceDisplayableManager*>(clientData);
  for (Picture* picture : self->Pictures) {
    if (picture->Logic == caller) self->UpdatePicture(*picture);
  }
  self->RequestRender();
}

void vtkRPVolumeSliceDisplayableManager::OnViewStateModified() {
  // SliceVisible may have changed (3D), nothing else here depends on the view state.
  for (Picture* picture : this->Pictures) this->UpdatePicture(*picture);
  this->RequestRender();
}

void vtkRPVolumeSliceDisplayableManager::UpdatePicture(Picture& picture) {
  vtkRPSliceLogic* logic = picture.Logic;
  const bool hasImage = logic && logic->HasImage();
  vtkRPSliceNode* node = logic ? logic->GetSliceNode() : nullptr;
  // A slice view always shows its picture; the 3D view where the node says "show in 3D".
  const bool visible = hasImage && (this->GetView()->IsSlice() || (node && node->GetSliceVisible()));
  picture.QuadActor->SetVisibility(visible);
  if (!visible) return;
  // The quad covers the picture's pixels (centres ± half a pixel), in plane coordinates.
  const double* b = logic->GetPlaneBounds();
  const double h = 0.5 * logic->GetPixelSpacing();
  picture.Quad->SetOrigin(b[0] - h, b[2] - h, 0);
  picture.Quad->SetPoint1(b[1] + h, b[2] - h, 0);
  picture.Quad->SetPoint2(b[0] - h, b[3] + h, 0);
}

