#pragma once
// A renderer's picture kept from one frame to the next (a VTK render pass). A frame in which
// something the renderer draws has changed — a prop shown or hidden, its redraw time (mapper
// input, property, texture, matrix), the camera, a light, the viewport's size — renders the
// props as usual (vtkRenderStepsPass) into a colour and a depth texture; every frame then copies
// both into the window by one framebuffer blit (the depth texture takes the window's depth
// format for it; VTK's depth-blit quad where it cannot). The 3D view's models are still while a tool moves and the slices follow it: such a
// frame costs the two copies instead of rasterizing every model again (on Mesa's llvmpipe the
// knee's models took ~20 ms of a frame at their light level of detail), and the moving layer —
// tools, the slices in 3D — is drawn on top by the next renderer, depth-tested against the kept
// depth so the models still hide what is behind them.
#include <vector>

#include <vtkDepthImageProcessingPass.h>
#include <vtkNew.h>

class vtkOpenGLFramebufferObject;
class vtkTextureObject;

class vtkRPCachedRenderPass : public vtkDepthImageProcessingPass {
 public:
  static vtkRPCachedRenderPass* New();
  vtkTypeMacro(vtkRPCachedRenderPass, vtkDepthImageProcessingPass);

  void Render(const vtkRenderState* s) override;
  void ReleaseGraphicsResources(vtkWindow* window) override;

  /// Off: every frame renders the props (what the pass does without a kept picture).
  void SetCaching(bool caching);
  bool GetCaching() const { return this->Caching; }
  /// True when the last frame rendered the props, false when it copied the kept picture.
  bool GetLastFrameRendered() const { return this->LastFrameRendered; }
  /// Frames that rendered the props, and frames that copied the kept picture.
  int GetNumberOfRenders() const { return this->Renders; }
  int GetNumberOfCopies() const { return this->Copies; }

 protected:
  vtkRPCachedRenderPass();
  ~vtkRPCachedRenderPass() override;

 private:
  vtkRPCachedRenderPass(const vtkRPCachedRenderPass&) = delete;
  void operator=(const vtkRPCachedRenderPass&) = delete;

  /// Everything the kept picture depends on, as numbers compared frame to frame.
  static std::vector<unsigned long long> Signature(const vtkRenderState* s, int width, int height);

  vtkOpenGLFramebufferObject* Framebuffer = nullptr;
  vtkTextureObject* Color = nullptr;
  vtkTextureObject* Depth = nullptr;
  std::vector<unsigned long long> Kept;  // the signature the textures were rendered with
  bool Valid = false;
  bool DepthByBlit = false;       // the depth texture has the window's format: blit it
  bool DepthBlitChecked = false;  // the first depth blit was checked for a GL error
  bool Caching = true;
  bool LastFrameRendered = false;
  int Renders = 0;
  int Copies = 0;
};
