#include "vtkRPCachedRenderPass.h"

#include <cstdint>
#include <cstring>

#include <vtk_glew.h>
#include <vtkCamera.h>
#include <vtkLight.h>
#include <vtkLightCollection.h>
#include <vtkObjectFactory.h>
#include <vtkOpenGLError.h>
#include <vtkOpenGLFramebufferObject.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkOpenGLState.h>
#include <vtkProp.h>
#include <vtkRenderState.h>
#include <vtkRenderStepsPass.h>
#include <vtkRenderer.h>
#include <vtkTextureObject.h>

vtkStandardNewMacro(vtkRPCachedRenderPass);

vtkRPCachedRenderPass::vtkRPCachedRenderPass() {
  // The usual steps (camera, lights, opaque, translucent blended in drawing order, overlay):
  // see-through tissue is blended without VTK's order-independent transparency, whose
  // full-screen float passes cost a software renderer more than the rest of the frame.
  vtkNew<vtkRenderStepsPass> steps;
  this->SetDelegatePass(steps);
  this->Color = vtkTextureObject::New();
  this->Depth = vtkTextureObject::New();
}

vtkRPCachedRenderPass::~vtkRPCachedRenderPass() {
  if (this->Framebuffer) this->Framebuffer->Delete();
  this->Color->Delete();
  this->Depth->Delete();
}

void vtkRPCachedRenderPass::SetCaching(bool caching) {
  this->Caching = caching;
  this->Valid = false;
}

namespace {
// Values in single precision: rendering into the textures swaps the renderer's camera for a copy
// and back (vtkImageProcessingPass), which touches their modification times and moves the view
// angle by ~1e-6 degrees through tan/atan; neither changes a pixel.
void AppendValues(std::vector<unsigned long long>& signature, const double* values, int n) {
  for (int i = 0; i < n; ++i) {
    const float value = static_cast<float>(values[i]);
    std::uint32_t bits = 0;
    std::memcpy(&bits, &value, sizeof bits);
    signature.push_back(bits);
  }
}
// The depth format of the window's own framebuffer, so that the kept depth copies back by a blit
// (a memory copy on Mesa, ~0.1 ms for 700×550, where VTK's depth-blit quad writing gl_FragDepth
// cost ~1.2 ms); -1 for a format a depth texture cannot take (depth-stencil).
int WindowDepthFormat(vtkOpenGLRenderWindow* window) {
  vtkOpenGLFramebufferObject* framebuffer = window->GetRenderFramebuffer();
  vtkTextureObject* depth = framebuffer ? framebuffer->GetDepthAttachmentAsTextureObject() : nullptr;
  switch (depth ? depth->GetInternalFormat(VTK_FLOAT, 1, false) : 0) {
    case GL_DEPTH_COMPONENT16: return vtkTextureObject::Fixed16;
    case GL_DEPTH_COMPONENT24: return vtkTextureObject::Fixed24;
    case GL_DEPTH_COMPONENT32: return vtkTextureObject::Fixed32;
    case GL_DEPTH_COMPONENT32F: return vtkTextureObject::Float32;
    default: return -1;
  }
}
}  // namespace

// The renderer and its camera by value, the lights and props by modification time.
std::vector<unsigned long long> vtkRPCachedRenderPass::Signature(const vtkRenderState* s, int width, int height) {
  vtkRenderer* renderer = s->GetRenderer();
  std::vector<unsigned long long> signature = {static_cast<unsigned long long>(width),
                                               static_cast<unsigned long long>(height)};
  AppendValues(signature, renderer->GetBackground(), 3);
  AppendValues(signature, renderer->GetBackground2(), 3);
  signature.push_back(static_cast<unsigned long long>(renderer->GetGradientBackground()));
  if (vtkCamera* camera = renderer->GetActiveCamera()) {
    AppendValues(signature, camera->GetPosition(), 3);
    AppendValues(signature, camera->GetFocalPoint(), 3);
    AppendValues(signature, camera->GetViewUp(), 3);
    AppendValues(signature, camera->GetClippingRange(), 2);
    const double lens[3] = {camera->GetViewAngle(), camera->GetParallelScale(), double(camera->GetParallelProjection())};
    AppendValues(signature, lens, 3);
  }
  vtkLightCollection* lights = renderer->GetLights();
  lights->InitTraversal();
  while (vtkLight* light = lights->GetNextItem()) signature.push_back(light->GetMTime());
  // The props VTK is about to draw (the visible ones) and when each last changed its look.
  for (int i = 0; i < s->GetPropArrayCount(); ++i) {
    vtkProp* prop = s->GetPropArray()[i];
    signature.push_back(static_cast<unsigned long long>(reinterpret_cast<std::uintptr_t>(prop)));
    signature.push_back(prop->GetRedrawMTime());
  }
  return signature;
}

void vtkRPCachedRenderPass::Render(const vtkRenderState* s) {
  vtkOpenGLClearErrorMacro();
  this->NumberOfRenderedProps = 0;
  vtkRenderer* renderer = s->GetRenderer();
  auto* window = vtkOpenGLRenderWindow::SafeDownCast(renderer->GetRenderWindow());
  if (!this->Caching || !window || !this->DelegatePass || s->GetFrameBuffer() || window->GetMultiSamples() > 1) {
    // Nothing kept, not an OpenGL window, rendered inside another pass's framebuffer, or a
    // multisampled window (a blit into it from single-sampled textures is not allowed
    // everywhere): the props straight into the window, no copies.
    if (this->DelegatePass) this->DelegatePass->Render(s);
    if (this->DelegatePass) this->NumberOfRenderedProps = this->DelegatePass->GetNumberOfRenderedProps();
    this->LastFrameRendered = true;
    ++this->Renders;
    return;
  }
  int width = 0, height = 0, x = 0, y = 0;
  renderer->GetTiledSizeAndOrigin(&width, &height, &x, &y);
  if (width <= 0 || height <= 0) return;

  this->Color->SetContext(window);
  if (!this->Color->GetHandle()) this->Color->Create2D(width, height, 4, VTK_UNSIGNED_CHAR, false);
  this->Color->Resize(width, height);
  this->Depth->SetContext(window);
  if (!this->Depth->GetHandle()) {
    const int format = WindowDepthFormat(window);
    this->DepthByBlit = format >= 0;
    this->DepthBlitChecked = false;
    this->Depth->AllocateDepth(width, height, format >= 0 ? format : vtkTextureObject::Float32);
  }
  this->Depth->Resize(width, height);
  if (!this->Framebuffer) {
    this->Framebuffer = vtkOpenGLFramebufferObject::New();
    this->Framebuffer->SetContext(window);
  }

  this->LastFrameRendered = !this->Valid || Signature(s, width, height) != this->Kept;
  if (this->LastFrameRendered) {
    this->Framebuffer->SaveCurrentBindingsAndBuffers();
    this->RenderDelegate(s, width, height, width, height, this->Framebuffer, this->Color, this->Depth);
    this->Framebuffer->RestorePreviousBindingsAndBuffers();
    this->NumberOfRenderedProps = this->DelegatePass->GetNumberOfRenderedProps();
    // Taken again after rendering: props that settle while they render (a text actor lays out
    // its text on its first frames) would otherwise make the next frame render again.
    this->Kept = Signature(s, width, height);
    this->Valid = true;
    ++this->Renders;
  } else {
    ++this->Copies;
  }

  // The kept picture into the window at the renderer's viewport.
  vtkOpenGLState* state = window->GetState();
  this->Framebuffer->SaveCurrentBindingsAndBuffers(this->Framebuffer->GetReadMode());
  this->Framebuffer->Bind(this->Framebuffer->GetReadMode());
  this->Framebuffer->ActivateReadBuffer(0);
  state->vtkglViewport(x, y, width, height);
  state->vtkglScissor(x, y, width, height);
  if (this->DepthByBlit && !this->DepthBlitChecked) {
    for (int i = 0; i < 16 && glGetError() != GL_NO_ERROR; ++i) {
    }
  }
  const GLbitfield buffers = GL_COLOR_BUFFER_BIT | (this->DepthByBlit ? GL_DEPTH_BUFFER_BIT : 0);
  state->vtkglBlitFramebuffer(0, 0, width, height, x, y, x + width, y + height, buffers, GL_NEAREST);
  if (this->DepthByBlit && !this->DepthBlitChecked) {
    // A driver that refuses the depth blit (formats it deems different): colour again, depth by quad.
    this->DepthBlitChecked = true;
    if (glGetError() != GL_NO_ERROR) {
      this->DepthByBlit = false;
      state->vtkglBlitFramebuffer(0, 0, width, height, x, y, x + width, y + height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
  }
  this->Framebuffer->RestorePreviousBindingsAndBuffers(this->Framebuffer->GetReadMode());
  if (!this->DepthByBlit) window->TextureDepthBlit(this->Depth, 0, 0, width, height, x, y, x + width, y + height);
  vtkOpenGLCheckErrorMacro("failed after copying the kept picture");
}

void vtkRPCachedRenderPass::ReleaseGraphicsResources(vtkWindow* window) {
  this->Superclass::ReleaseGraphicsResources(window);
  if (this->Framebuffer) {
    this->Framebuffer->Delete();
    this->Framebuffer = nullptr;
  }
  this->Color->ReleaseGraphicsResources(window);
  this->Depth->ReleaseGraphicsResources(window);
  this->Valid = false;
}
