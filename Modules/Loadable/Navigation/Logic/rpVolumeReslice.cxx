#include "rpVolumeReslice.h"

#include <algorithm>
#include <cmath>

#include <vtkImageData.h>
#include <vtkImageReslice.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include "vtkRPScalarVolumeNode.h"

namespace rp {

void SliceToRASForOrientation(SliceOrientation orientation, const double centerRAS[3], vtkMatrix4x4* sliceToRAS) {
  sliceToRAS->Identity();
  // Columns: slice x, slice y, normal.
  double x[3], y[3], n[3];
  switch (orientation) {
    case SliceOrientation::Axial:
      x[0] = 1, x[1] = 0, x[2] = 0;
      y[0] = 0, y[1] = 1, y[2] = 0;
      n[0] = 0, n[1] = 0, n[2] = 1;
      break;
    case SliceOrientation::Sagittal:
      x[0] = 0, x[1] = 1, x[2] = 0;
      y[0] = 0, y[1] = 0, y[2] = 1;
      n[0] = 1, n[1] = 0, n[2] = 0;
      break;
    case SliceOrientation::Coronal:
    default:
      x[0] = 1, x[1] = 0, x[2] = 0;
      y[0] = 0, y[1] = 0, y[2] = 1;
      n[0] = 0, n[1] = -1, n[2] = 0;  // x × y, so the frame stays right-handed
      break;
  }
  for (int r = 0; r < 3; ++r) {
    sliceToRAS->SetElement(r, 0, x[r]);
    sliceToRAS->SetElement(r, 1, y[r]);
    sliceToRAS->SetElement(r, 2, n[r]);
    sliceToRAS->SetElement(r, 3, centerRAS[r]);
  }
}

void SliceToRASForTool(const vtkMatrix4x4* toolTipToRAS, vtkMatrix4x4* sliceToRAS) {
  // slice x = tool x, slice y = tool z (shaft), normal = x × y = -tool y.
  sliceToRAS->Identity();
  for (int r = 0; r < 3; ++r) {
    sliceToRAS->SetElement(r, 0, toolTipToRAS->GetElement(r, 0));
    sliceToRAS->SetElement(r, 1, toolTipToRAS->GetElement(r, 2));
    sliceToRAS->SetElement(r, 2, -toolTipToRAS->GetElement(r, 1));
    sliceToRAS->SetElement(r, 3, toolTipToRAS->GetElement(r, 3));
  }
}

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
