#pragma once
// Re-slices a background and an optional foreground volume on one RAS-aligned plane through a
// point and blends them (foreground over background with an opacity) into one RGBA image shown
// by an image actor placed in RAS. Both layers share one output grid that covers both volumes,
// so the blend needs no resampling; each volume's parent transforms are honoured.
#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include "rpSliceGeometry.h"

class vtkImageActor;
class vtkImageBlend;
class vtkImageMapToColors;
class vtkImageReslice;
class vtkLookupTable;
class vtkMatrix4x4;
class vtkRPScalarVolumeNode;

namespace rp {

class SliceReslicer {
 public:
  explicit SliceReslicer(ViewKind orientation);
  ~SliceReslicer();
  SliceReslicer(const SliceReslicer&) = delete;
  SliceReslicer& operator=(const SliceReslicer&) = delete;

  /// Either may be null. Call Update() afterwards.
  void SetVolumes(vtkRPScalarVolumeNode* background, vtkRPScalarVolumeNode* foreground, double foregroundOpacity);
  void SetSlicePoint(const double pointRAS[3]);
  /// Recomputes the plane, the output grid and the window/level tables (cheap); the re-slicing
  /// itself runs lazily when the actor renders.
  void Update();

  vtkImageActor* GetActor() const { return this->Actor; }
  bool HasImage() const { return this->Background != nullptr; }
  /// Slice plane frame → RAS (columns X, Y, normal; origin on the plane).
  vtkMatrix4x4* GetSliceToRAS() const { return this->SliceToRAS; }
  /// In-plane size of an output pixel (mm).
  double GetPixelSpacing() const { return this->PixelSpacing; }

 private:
  struct Layer;
  void UpdateLayer(Layer& layer, vtkRPScalarVolumeNode* volume, bool transparentOutside);

  ViewKind Orientation;
  vtkRPScalarVolumeNode* Background = nullptr;  // not owned; the caller clears when removed
  vtkRPScalarVolumeNode* Foreground = nullptr;
  double ForegroundOpacity = 0.5;
  double SlicePoint[3] = {0, 0, 0};
  double PixelSpacing = 1.0;
  Layer* Layers[2];
  vtkNew<vtkImageBlend> Blend;
  vtkNew<vtkImageActor> Actor;
  vtkNew<vtkMatrix4x4> SliceToRAS;
};

}  // namespace rp
