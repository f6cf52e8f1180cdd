#pragma once
// Re-slicing a volume on a plane through a point (seed sections 3.2.3 and 4): the axial,
// sagittal and coronal planes of the scene, or the plane of a tool. A slice is described by its
// SliceToRAS matrix: columns are the in-plane x and y axes and the normal, translation the centre.
// The planes come from the one definition of the slice frames, vtkRPSliceNode
// (ComputeSliceToRAS("Axial" | "Sagittal" | "Coronal", point), ComputeSliceToRASForTool), so a
// re-sliced picture is oriented as the viewer shows that slice (x → screen right, y → up).
#include <vtkSmartPointer.h>

class vtkImageData;
class vtkMatrix4x4;
class vtkRPScalarVolumeNode;

namespace rp {

struct ResliceOptions {
  double FieldOfView[2] = {200.0, 200.0};  // mm
  double Spacing = 0.0;                    // mm per pixel; 0: the volume's smallest spacing
  bool Linear = true;                      // trilinear (true) or nearest neighbour
  double Background = 0.0;                 // value outside the volume
};

/// Samples the volume (with its parent transforms) on the slice. The output image is 2-D
/// (z extent 0..0), centred on the slice origin (its middle pixel, for odd sizes, is the
/// centre), with the output's origin and spacing in slice coordinates: pixel (i, j) sits at
/// SliceToRAS · (origin + spacing·(i, j, 0)).
vtkSmartPointer<vtkImageData> ResliceVolume(vtkRPScalarVolumeNode* volume, const vtkMatrix4x4* sliceToRAS,
                                            const ResliceOptions& options = {});

}  // namespace rp
