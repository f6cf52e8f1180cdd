#ifndef vtkRPSliceLogic_h
#define vtkRPSliceLogic_h
// The picture of one slice node, computed once for every view that draws it (Slicer's
// vtkMRMLSliceLogic + vtkMRMLSliceLayerLogic): the background and foreground volumes re-sliced
// on the node's plane straight to colours, the foreground blended over the background with the
// node's opacity, and the label layer (a segmentation, nearest neighbour, in its segments'
// colours) over both with the label opacity — all in one pass per pixel (rp::CompositeSlice),
// where VTK's way is a vtkImageResliceToColors per layer and a vtkImageBlend.
// Compositing here, not with translucent actors, keeps the views' rendering opaque (a
// translucent prop costs a full-screen order-independent-transparency pass per frame).
//
// The output is RGBA. Its alpha marks where there is patient: the background's voxels above the
// volume's air threshold (outside the volume is transparent too), so the 3D view lets the models
// through the air; slice views draw only the colours, on black. A segmentation without a
// background is drawn alone, on its own grid: its labelled voxels opaque, the rest transparent.
//
// It observes its slice node and the layer volumes (window/level, data, transforms) and fires
// ModifiedEvent when the picture changes. Work is in proportion to what changed: the plane,
// grid and tables are recomputed on events (cheap); the re-slicing itself runs lazily when a
// view renders, and only if the plane, grid, tables or data changed.
#include <vtkNew.h>
#include <vtkObject.h>
#include <vtkWeakPointer.h>

class vtkAlgorithmOutput;
class vtkCallbackCommand;
class vtkMatrix4x4;
class vtkRPImageNode;
class vtkRPScalarVolumeNode;
class vtkRPScene;
class vtkRPSegmentationNode;
class vtkRPSliceNode;
class vtkRPSlicePicture;

class vtkRPSliceLogic : public vtkObject {
 public:
  static vtkRPSliceLogic* New();
  vtkTypeMacro(vtkRPSliceLogic, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The slice node drawn (observed) and its scene (where the layer volumes are looked up).
  void SetSliceNode(vtkRPScene* scene, vtkRPSliceNode* sliceNode);
  vtkRPSliceNode* GetSliceNode() const { return this->SliceNode; }

  /// True when there is a background volume, or a segmentation, with voxels to show.
  bool HasImage() const { return this->Visible; }
  /// The RGBA picture (alpha: patient mask). Its pixel (i, j) is at
  /// GridToRAS · (i, j, 0), i.e. origin and spacing are in plane coordinates.
  vtkAlgorithmOutput* GetOutputPort();
  /// Plane coordinates → RAS (columns right, up, normal; origin on the plane).
  vtkMatrix4x4* GetPlaneToRAS() const { return this->PlaneToRAS; }
  /// Plane-coordinate rectangle the picture covers: xmin, xmax, ymin, ymax (pixel centres).
  const double* GetPlaneBounds() const { return this->PlaneBounds; }
  /// In-plane size of a picture pixel (mm).
  double GetPixelSpacing() const { return this->PixelSpacing; }
  /// Times the re-slicing actually ran (tests and benchmarks: "re-slice only what changed").
  int GetNumberOfReslices() const;
  /// Starts making the picture on a worker thread if it is out of date, so that it is ready (or
  /// nearly) when a view updates the output port; the render scheduler calls it for the views it
  /// is about to render. The output is the same as without it.
  void StartPicture();
  /// Waits for a picture StartPicture() began (the scheduler, before its tick ends: volumes may
  /// change between ticks).
  void WaitForPicture();
  /// Pictures the output took from a StartPicture() (tests and benchmarks).
  int GetNumberOfPicturesMadeAhead() const;

  /// The value under which a volume is air (transparent in 3D): −400 HU for a CT (its values go
  /// below −900), else 10 % of the way from the 1st to the 99th percentile.
  static double ComputeAirThreshold(vtkRPScalarVolumeNode* volume);

  /// The rectangle (xmin, xmax, ymin, ymax, in plane coordinates of `planeToRAS`) that an
  /// image's voxel centres cover when projected on the plane, with the image's parent transforms;
  /// only those of `extent` when given.
  static void ComputePlaneBounds(vtkRPImageNode* image, const vtkMatrix4x4* planeToRAS, double bounds[4],
                                 const int* extent = nullptr);
  /// What views fit to and centre on when they show an image: a volume's whole extent; a
  /// segmentation's labelled voxels (a small segment on a CT's grid is not lost in the middle of
  /// the field of view), its whole extent when none is labelled. Cached for the last image asked.
  static void ComputeShownExtent(vtkRPImageNode* image, int extent[6]);
  /// RAS bounds of the voxel centres of ComputeShownExtent (as vtkRPImageNode::GetRASBounds).
  static void ComputeShownRASBounds(vtkRPImageNode* image, double bounds[6]);

  /// Re-reads the node and volumes now (the observers call it; tests may too).
  void Refresh();

 protected:
  vtkRPSliceLogic();
  ~vtkRPSliceLogic() override;

 private:
  vtkRPSliceLogic(const vtkRPSliceLogic&) = delete;
  void operator=(const vtkRPSliceLogic&) = delete;
  struct Layer;
  static void OnEvent(vtkObject* caller, unsigned long event, void* clientData, void* callData);
  void ObserveLayers(vtkRPScalarVolumeNode* background, vtkRPScalarVolumeNode* foreground, vtkRPSegmentationNode* label);
  bool UpdateLayer(Layer& layer, vtkRPScalarVolumeNode* volume, bool isBackground);
  bool UpdateLabelLayer(Layer& layer, vtkRPSegmentationNode* segmentation);

  vtkWeakPointer<vtkRPScene> Scene;
  vtkWeakPointer<vtkRPSliceNode> SliceNode;
  unsigned long SliceNodeTag = 0;
  Layer* Layers[3];  // background, foreground, label
  vtkRPSlicePicture* Picture;  // the pipeline source the views update (owned)
  vtkNew<vtkMatrix4x4> PlaneToRAS;
  vtkNew<vtkCallbackCommand> Callback;
  double PlaneBounds[4] = {0, 0, 0, 0};
  double PixelSpacing = 1.0;
  bool Visible = false;
  bool SliceVisible = true;  // the node's "show in 3D", so the 3D view hears when it changes
};

#endif
