#include "vtkRPViewportImageActor.h"

#include <algorithm>

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkObjectFactory.h>
#include <vtkOpenGLFramebufferObject.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkOpenGLRenderer.h>
#include <vtkOpenGLState.h>
#include <vtkPointData.h>
#include <vtkTextureObject.h>
#include <vtk_glew.h>

vtkStandardNewMacro(vtkRPViewportImageActor);

vtkRPViewportImageActor::vtkRPViewportImageActor() { this->PickableOff(); }

vtkRPViewportImageActor::~vtkRPViewportImageActor() { this->ReleaseGraphicsResources(nullptr); }

void vtkRPViewportImageActor::SetInputData(vtkImageData* picture) {
  if (picture == this->Input) return;
  this->Input = picture;
  this->UploadedTime = 0;
  this->Modified();
}

void vtkRPViewportImageActor::ReleaseGraphicsResources(vtkWindow* window) {
  if (this->Framebuffer) {
    if (window) this->Framebuffer->ReleaseGraphicsResources(window);
    this->Framebuffer->Delete();
    this->Framebuffer = nullptr;
  }
  if (this->Texture) {
    if (window) this->Texture->ReleaseGraphicsResources(window);
    this->Texture->Delete();
    this->Texture = nullptr;
  }
  this->UploadedTime = 0;
}

int vtkRPViewportImageActor::RenderOpaqueGeometry(vtkViewport* viewport) {
  auto* renderer = vtkOpenGLRenderer::SafeDownCast(viewport);
  auto* window = renderer ? vtkOpenGLRenderWindow::SafeDownCast(renderer->GetRenderWindow()) : nullptr;
  if (!window || !this->Input || renderer->GetSelector()) return 0;
  int width = 0, height = 0, x0 = 0, y0 = 0;
  renderer->GetTiledSizeAndOrigin(&width, &height, &x0, &y0);
  int dims[3];
  this->Input->GetDimensions(dims);
  vtkDataArray* scalars = this->Input->GetPointData()->GetScalars();
  if (dims[0] != width || dims[1] != height || !scalars || scalars->GetNumberOfComponents() != 4 ||
      scalars->GetDataType() != VTK_UNSIGNED_CHAR) {
    return 0;
  }
  if (this->Texture && this->Texture->GetContext() != window) this->ReleaseGraphicsResources(this->Texture->GetContext());
  vtkOpenGLState* state = window->GetState();
  if (!this->Texture) {
    this->Texture = vtkTextureObject::New();
    this->Texture->SetContext(window);
    this->Framebuffer = vtkOpenGLFramebufferObject::New();
    this->Framebuffer->SetContext(window);
  }
  const bool resized = int(this->Texture->GetWidth()) != width || int(this->Texture->GetHeight()) != height;
  if (resized || this->UploadedTime < this->Input->GetMTime() || this->UploadedTime < scalars->GetMTime()) {
    if (resized) {
      this->Texture->Create2DFromRaw(static_cast<unsigned int>(width), static_cast<unsigned int>(height), 4,
                                     VTK_UNSIGNED_CHAR, scalars->GetVoidPointer(0));
    } else {
      // Into the texture's storage as it is (re-creating it made the driver allocate and
      // fault in fresh pages every frame).
      this->Texture->Activate();
      glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, scalars->GetVoidPointer(0));
      this->Texture->Deactivate();
    }
    this->UploadedTime = std::max(this->Input->GetMTime(), scalars->GetMTime());
    ++this->Uploads;
    if (resized) {
      state->PushFramebufferBindings();
      this->Framebuffer->Bind();
      this->Framebuffer->AddColorAttachment(0, this->Texture);
      state->PopFramebufferBindings();
    }
  }
  // Into the framebuffer VTK draws to (its render framebuffer, or a pass's), at the viewport.
  // The scissor test is off for the copy: a blit within the viewport needs none, and with it
  // on Mesa would rasterize the copy instead of copying memory.
  state->PushReadFramebufferBinding();
  this->Framebuffer->Bind(GL_READ_FRAMEBUFFER);
  this->Framebuffer->ActivateReadBuffer(0);
  {
    vtkOpenGLState::ScopedglEnableDisable scissor(state, GL_SCISSOR_TEST);
    state->vtkglDisable(GL_SCISSOR_TEST);
    state->vtkglBlitFramebuffer(0, 0, width, height, x0, y0, x0 + width, y0 + height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  }
  state->PopReadFramebufferBinding();
  ++this->Draws;
  return 1;
}
