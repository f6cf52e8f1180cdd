#include "vtkRPVolumeSliceDisplayableManager.h"

#include <algorithm>
#include <string>

#include <vtkActor.h>
#include <vtkAlgorithm.h>
#include <vtkAlgorithmOutput.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOpenGLShaderProperty.h>
#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkShader.h>
#include <vtkTexture.h>

#include "rpPictureResample.h"
#include "rpSliceComposite.h"
#include "rpView.h"
#include "vtkRPSliceLogic.h"
#include "vtkRPSliceNode.h"
#include "vtkRPViewportImageActor.h"

vtkStandardNewMacro(vtkRPVolumeSliceDisplayableManager);

// One slice node's picture in this view. In 3D a quad in plane coordinates over the picture's
// patient pixels, placed by the plane's matrix, textured with the RGBA picture as it is. In a
// slice view the picture resampled onto the view's pixels (Screen), put into the framebuffer as
// it is (ScreenActor).
struct vtkRPVolumeSliceDisplayableManager::Picture {
  vtkRPSliceLogic* Logic = nullptr;
  unsigned long Tag = 0;
  vtkNew<vtkPolyData> Quad;
  double QuadKey[6] = {-1, 0, 0, 0, 0, 0};  // the picture it was fitted to: time, first pixel, spacing, size
  vtkNew<vtkPolyDataMapper> QuadMapper;
  vtkNew<vtkTexture> Texture;
  vtkNew<vtkActor> QuadActor;
  vtkNew<vtkImageData> Screen;
  vtkNew<vtkRPViewportImageActor> ScreenActor;
  // What Screen was resampled from: the picture's time, the viewport's size, the pixel map.
  double ScreenKey[9] = {-1, 0, 0, 0, 0, 0, 0, 0, 0};
  std::string ScreenText;  // the view's corner text drawn into it
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
    this->Pictures.push_back(picture);
    if (logic) picture->Tag = logic->AddObserver(vtkCommand::ModifiedEvent, this->LogicCallback);
    if (view->IsSlice()) {
      picture->ScreenActor->SetInputData(picture->Screen);
      view->GetRenderer()->AddViewProp(picture->ScreenActor);
      this->UpdatePicture(*picture);
      continue;
    }
    if (logic) picture->Texture->SetInputConnection(logic->GetOutputPort());
    picture->Texture->InterpolateOn();
    picture->Texture->SetColorModeToDirectScalars();
    {
      // No area until the first render fits it to its picture (UpdateQuad).
      vtkNew<vtkPoints> corners;
      corners->SetNumberOfPoints(4);
      vtkNew<vtkFloatArray> tcoords;
      tcoords->SetNumberOfComponents(2);
      tcoords->SetNumberOfTuples(4);
      for (vtkIdType k = 0; k < 4; ++k) {
        corners->SetPoint(k, 0, 0, 0);
        tcoords->SetTuple2(k, 0, 0);
      }
      vtkNew<vtkCellArray> quad;
      const vtkIdType ids[4] = {0, 1, 2, 3};
      quad->InsertNextCell(4, ids);
      picture->Quad->SetPoints(corners);
      picture->Quad->GetPointData()->SetTCoords(tcoords);
      picture->Quad->SetPolys(quad);
    }
    picture->QuadMapper->SetInputData(picture->Quad);
    SkipVertexShift(picture->QuadMapper);  // moves with its slice
    // The air is cut away rather than blended: discarded fragments write no depth, so the three
    // planes and the models behind them are drawn correctly without sorting or peeling.
    vtkOpenGLShaderProperty::SafeDownCast(picture->QuadActor->GetShaderProperty())
        ->AddShaderReplacement(vtkShader::Fragment, "//VTK::TCoord::Impl", true,
                               "//VTK::TCoord::Impl\n  if (gl_FragData[0].a < 0.5) { discard; }\n", false);
    picture->QuadActor->SetMapper(picture->QuadMapper);
    picture->QuadActor->SetTexture(picture->Texture);
    picture->QuadActor->ForceOpaqueOn();
    picture->QuadActor->GetProperty()->LightingOff();
    picture->QuadActor->GetProperty()->SetAmbient(1.0);
    picture->QuadActor->GetProperty()->SetDiffuse(0.0);
    if (logic) picture->QuadActor->SetUserMatrix(logic->GetPlaneToRAS());
    // The slices move with the slice point, so they are drawn with what moves (layer 1), over
    // the models' kept picture.
    view->GetOverlayRenderer()->AddViewProp(picture->QuadActor);
    this->UpdatePicture(*picture);
  }
  // A slice view makes its screen picture when it renders: the camera and size are known then,
  // and many slice moves between two frames cost one resampling. The 3D view fits its quads to
  // the pictures then, once however often they changed.
  this->RenderCallback->SetClientData(this);
  this->RenderCallback->SetCallback([](vtkObject*, unsigned long, void* clientData, void*) {
    auto* self = static_cast<vtkRPVolumeSliceDisplayableManager*>(clientData);
    for (Picture* picture : self->Pictures) {
      if (self->InSliceView()) self->UpdateScreenPicture(*picture);
      else self->UpdateQuad(*picture);
    }
  });
  this->RenderTarget = view->IsSlice() ? view->GetRenderer() : view->GetOverlayRenderer();
  this->RenderTag = this->RenderTarget->AddObserver(vtkCommand::StartEvent, this->RenderCallback);
}

// The picture resampled at the slice view's pixels. Pixel (i, j)'s centre is a point of the
// plane (the slice camera looks along the normal with a parallel projection); its place in the
// picture follows from the plane's coordinates, the picture's first pixel and its spacing.
void vtkRPVolumeSliceDisplayableManager::UpdateScreenPicture(Picture& picture) {
  vtkRPSliceLogic* logic = picture.Logic;
  vtkRenderer* renderer = this->RenderTarget;
  if (!logic || !renderer || !picture.ScreenActor->GetVisibility()) return;
  vtkAlgorithm* producer = logic->GetOutputPort()->GetProducer();
  producer->Update();
  vtkImageData* source = vtkImageData::SafeDownCast(producer->GetOutputDataObject(0));
  int width = 0, height = 0, x0 = 0, y0 = 0;
  renderer->GetTiledSizeAndOrigin(&width, &height, &x0, &y0);
  vtkCamera* camera = renderer->GetActiveCamera();
  if (!source || width <= 0 || height <= 0) return;
  // Display pixel centre → normalized device coordinates → RAS → plane → picture pixel.
  vtkNew<vtkMatrix4x4> worldToDevice, deviceToWorld, rasToPlane;
  worldToDevice->DeepCopy(camera->GetCompositeProjectionTransformMatrix(renderer->GetTiledAspectRatio(), -1, 1));
  vtkMatrix4x4::Invert(worldToDevice, deviceToWorld);
  vtkMatrix4x4::Invert(logic->GetPlaneToRAS(), rasToPlane);
  const double* bounds = logic->GetPlaneBounds();
  const double spacing = logic->GetPixelSpacing();
  auto pictureIndex = [&](double i, double j, double uv[2]) {
    const double device[4] = {2.0 * (i + 0.5) / width - 1.0, 2.0 * (j + 0.5) / height - 1.0, 0.0, 1.0};
    double ras[4], plane[4];
    deviceToWorld->MultiplyPoint(device, ras);
    for (int k = 0; k < 3; ++k) ras[k] /= ras[3];
    rasToPlane->MultiplyPoint(ras, plane);
    uv[0] = (plane[0] - bounds[0]) / spacing;
    uv[1] = (plane[1] - bounds[2]) / spacing;
  };
  rp::PixelMap map;
  double alongI[2], alongJ[2];
  pictureIndex(0, 0, map.Origin);
  pictureIndex(1, 0, alongI);
  pictureIndex(0, 1, alongJ);
  for (int c = 0; c < 2; ++c) {
    map.AlongI[c] = alongI[c] - map.Origin[c];
    map.AlongJ[c] = alongJ[c] - map.Origin[c];
  }
  // The same picture at the same pixels: nothing to do (a tool moving in the view, say). The
  // map, not the camera's time, decides: the camera is set again whenever the slice node is.
  const double key[9] = {double(source->GetMTime()), double(width), double(height), map.Origin[0], map.Origin[1],
                         map.AlongI[0], map.AlongI[1], map.AlongJ[0], map.AlongJ[1]};
  rp::View* view = this->GetView();
  const std::string text = view ? view->GetCornerString() : std::string();
  if (std::equal(key, key + 9, picture.ScreenKey) && text == picture.ScreenText) return;
  std::copy(key, key + 9, picture.ScreenKey);
  picture.ScreenText = text;
  int dims[3];
  picture.Screen->GetDimensions(dims);
  if (dims[0] != width || dims[1] != height || !picture.Screen->GetPointData()->GetScalars()) {
    picture.Screen->SetDimensions(width, height, 1);
    picture.Screen->AllocateScalars(VTK_UNSIGNED_CHAR, 4);
  }
  source->GetDimensions(dims);
  vtkDataArray* colours = source->GetPointData()->GetScalars();
  const bool usable = colours && colours->GetNumberOfComponents() == 4 && colours->GetDataType() == VTK_UNSIGNED_CHAR;
  rp::ResampleOpaqueRGBA(usable ? static_cast<const unsigned char*>(colours->GetVoidPointer(0)) : nullptr, dims[0], dims[1],
                         map, static_cast<unsigned char*>(picture.Screen->GetScalarPointer()), width, height);
  if (view) view->DrawCornerText(static_cast<unsigned char*>(picture.Screen->GetScalarPointer()), width, height);
  picture.Screen->GetPointData()->GetScalars()->Modified();
  picture.Screen->Modified();
}

void vtkRPVolumeSliceDisplayableManager::OnFinalize() {
  rp::View* view = this->GetView();
  if (this->RenderTarget) this->RenderTarget->RemoveObserver(this->RenderTag);
  this->RenderTarget = nullptr;
  for (Picture* picture : this->Pictures) {
    if (picture->Logic) picture->Logic->RemoveObserver(picture->Tag);
    if (view) view->GetOverlayRenderer()->RemoveViewProp(picture->QuadActor);
    if (view) view->GetRenderer()->RemoveViewProp(picture->ScreenActor);
    delete picture;
  }
  this->Pictures.clear();
}

bool vtkRPVolumeSliceDisplayableManager::InSliceView() const {
  const rp::View* view = this->GetView();
  return view && view->IsSlice();
}

vtkActor* vtkRPVolumeSliceDisplayableManager::GetSliceActor(int i) const {
  if (this->InSliceView() || i < 0 || i >= static_cast<int>(this->Pictures.size())) return nullptr;
  return this->Pictures[static_cast<size_t>(i)]->QuadActor;
}

vtkRPViewportImageActor* vtkRPVolumeSliceDisplayableManager::GetScreenPictureActor() const {
  return this->InSliceView() && !this->Pictures.empty() ? this->Pictures[0]->ScreenActor.GetPointer() : nullptr;
}

int vtkRPVolumeSliceDisplayableManager::GetNumberOfVisibleSlices() const {
  int visible = 0;
  for (Picture* picture : this->Pictures) {
    visible += (this->InSliceView() ? picture->ScreenActor->GetVisibility() : picture->QuadActor->GetVisibility()) ? 1 : 0;
  }
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
  if (this->GetView()->IsSlice()) {
    picture.ScreenActor->SetVisibility(hasImage);
    picture.QuadActor->SetVisibility(false);
    return;
  }
  const bool visible = hasImage && node && node->GetSliceVisible();
  picture.QuadActor->SetVisibility(visible);
}

// The quad over the picture's patient pixels (their bounding rectangle, pixel centres ± half a
// pixel) in plane coordinates, and the texture coordinates of those pixels; nothing where the
// picture is all air. Redone only when the picture changed.
void vtkRPVolumeSliceDisplayableManager::UpdateQuad(Picture& picture) {
  vtkRPSliceLogic* logic = picture.Logic;
  if (!logic || !picture.QuadActor->GetVisibility()) return;
  vtkAlgorithm* producer = logic->GetOutputPort()->GetProducer();
  producer->Update();
  auto* source = vtkImageData::SafeDownCast(producer->GetOutputDataObject(0));
  vtkDataArray* colours = source ? source->GetPointData()->GetScalars() : nullptr;
  if (!colours || colours->GetNumberOfComponents() != 4 || colours->GetDataType() != VTK_UNSIGNED_CHAR) return;
  int dims[3];
  source->GetDimensions(dims);
  const double* b = logic->GetPlaneBounds();
  const double spacing = logic->GetPixelSpacing();
  const double key[6] = {double(source->GetMTime()), b[0], b[2], spacing, double(dims[0]), double(dims[1])};
  if (std::equal(key, key + 6, picture.QuadKey)) return;
  std::copy(key, key + 6, picture.QuadKey);
  int extent[4];
  if (!rp::OpaqueExtent(static_cast<const std::uint32_t*>(colours->GetVoidPointer(0)), dims[0], dims[1], extent)) {
    extent[0] = extent[2] = 0;  // all air: a quad of no area
    extent[1] = extent[3] = -1;
  }
  // Pixel x's centre lies at b[0] + x · spacing; the quad runs from the first pixel's left edge
  // to the last one's right edge, and so do the texture coordinates (pixel x spans x/n … (x+1)/n).
  const double x0 = b[0] + (extent[0] - 0.5) * spacing, x1 = b[0] + (extent[1] + 0.5) * spacing;
  const double y0 = b[2] + (extent[2] - 0.5) * spacing, y1 = b[2] + (extent[3] + 0.5) * spacing;
  const float u0 = float(extent[0]) / dims[0], u1 = float(extent[1] + 1) / dims[0];
  const float v0 = float(extent[2]) / dims[1], v1 = float(extent[3] + 1) / dims[1];
  vtkPoints* corners = picture.Quad->GetPoints();
  corners->SetPoint(0, x0, y0, 0);
  corners->SetPoint(1, x1, y0, 0);
  corners->SetPoint(2, x1, y1, 0);
  corners->SetPoint(3, x0, y1, 0);
  corners->Modified();
  vtkDataArray* tcoords = picture.Quad->GetPointData()->GetTCoords();
  const float uv[4][2] = {{u0, v0}, {u1, v0}, {u1, v1}, {u0, v1}};
  for (int k = 0; k < 4; ++k) tcoords->SetTuple2(k, uv[k][0], uv[k][1]);
  tcoords->Modified();
  picture.Quad->Modified();
}
