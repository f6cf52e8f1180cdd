#ifndef vtkRPViewportImageActor_h
#define vtkRPViewportImageActor_h
// An RGBA picture exactly the size of its renderer's viewport, put into the framebuffer pixel
// for pixel by a framebuffer blit, not drawn as a textured quad. A slice view's picture is made
// at the view's own pixel grid (vtkRPVolumeSliceDisplayableManager), as Slicer's slice views do,
// so nothing is left to sample: on Mesa's llvmpipe a same-size blit is a memory copy (~0.1 ms for
// 700×550), where rasterizing the textured quad that covered the view cost 2.5–5 ms a frame.
// It writes colour only (no depth) and nothing while a hardware selector picks.
#include <vtkNew.h>
#include <vtkProp.h>
#include <vtkSmartPointer.h>

class vtkImageData;
class vtkOpenGLFramebufferObject;
class vtkTextureObject;
class vtkWindow;

class vtkRPViewportImageActor : public vtkProp {
 public:
  static vtkRPViewportImageActor* New();
  vtkTypeMacro(vtkRPViewportImageActor, vtkProp);

  /// The picture: 4-component unsigned char, one pixel per viewport pixel (row 0 at the bottom).
  /// A picture whose size differs from the viewport's is not drawn.
  void SetInputData(vtkImageData* picture);
  vtkImageData* GetInput() const { return this->Input; }

  int RenderOpaqueGeometry(vtkViewport* viewport) override;
  vtkTypeBool HasTranslucentPolygonalGeometry() override { return 0; }
  void ReleaseGraphicsResources(vtkWindow* window) override;

  /// Frames that put the picture into the framebuffer, and uploads of a changed picture (tests).
  int GetNumberOfDraws() const { return this->Draws; }
  int GetNumberOfUploads() const { return this->Uploads; }

 protected:
  vtkRPViewportImageActor();
  ~vtkRPViewportImageActor() override;

 private:
  vtkRPViewportImageActor(const vtkRPViewportImageActor&) = delete;
  void operator=(const vtkRPViewportImageActor&) = delete;

  vtkSmartPointer<vtkImageData> Input;
  vtkTextureObject* Texture = nullptr;
  vtkOpenGLFramebufferObject* Framebuffer = nullptr;
  vtkMTimeType UploadedTime = 0;
  int Draws = 0;
  int Uploads = 0;
};

#endif
