#include "rpVolumeReslice.h"

#include <algorithm>
#include <cmath>

#include <vtkImageData.h>
#include <vtkImageReslice.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include "vtkRPScalarVolumeNode.h"

namespace rp {

vtkSmartPointer<vtkImageData> ResliceVolume(vtkRPScalarVolumeNode* volume, const vtkMatrix4x4* sliceToRAS,
                                            const ResliceOptions& options) {
  double spacing = options.Spacing;
  if (spacing <= 0) {
    double s[3];
    volume->GetSpacing(s);
    spacing = std::min({s[0], s[1], s[2]});
  }
  // Output (slice) coordinates → IJK of the volume: inverse(ToWorld · IJKToRAS) · SliceToRAS.
  vtkNew<vtkMatrix4x4> volumeToWorld, ijkToWorld, worldToIJK, sliceToIJK;
  volume->GetParentTransformToWorld(volumeToWorld);
  vtkMatrix4x4::Multiply4x4(volumeToWorld, volume->GetIJKToRASMatrix(), ijkToWorld);
  vtkMatrix4x4::Invert(ijkToWorld, worldToIJK);
  vtkMatrix4x4::Multiply4x4(worldToIJK, sliceToRAS, sliceToIJK);

  const int nx = std::max(1, static_cast<int>(std::lround(options.FieldOfView[0] / spacing)));
  const int ny = std::max(1, static_cast<int>(std::lround(options.FieldOfView[1] / spacing)));
  vtkNew<vtkImageReslice> reslice;
  reslice->SetInputData(volume->GetImageData());
  reslice->SetResliceAxes(sliceToIJK);
  reslice->SetOutputDimensionality(2);
  reslice->SetOutputSpacing(spacing, spacing, 1.0);
  reslice->SetOutputOrigin(-0.5 * (nx - 1) * spacing, -0.5 * (ny - 1) * spacing, 0.0);
  reslice->SetOutputExtent(0, nx - 1, 0, ny - 1, 0, 0);
  reslice->SetBackgroundLevel(options.Background);
  if (options.Linear) {
    reslice->SetInterpolationModeToLinear();
  } else {
    reslice->SetInterpolationModeToNearestNeighbor();
  }
  reslice->Update();
  auto output = vtkSmartPointer<vtkImageData>::New();
  output->ShallowCopy(reslice->GetOutput());
  return output;
}

}  // namespace rp
