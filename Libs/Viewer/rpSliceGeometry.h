#pragma once
// The views and their RAS-aligned slice frames. Screen axes follow the radiological convention
// 3D Slicer uses: axial seen from the feet (patient's left on screen right), coronal seen from
// the front, sagittal seen from the patient's left (anterior on screen left).
#include <string>

namespace rp {

enum class ViewKind { Axial = 0, Sagittal = 1, Coronal = 2, ThreeD = 3 };

struct SliceAxes {
  double X[3];       // screen right, RAS unit vector
  double Y[3];       // screen up
  double Normal[3];  // slice normal: S (axial), R (sagittal), A (coronal); scrolling moves along it
  int NormalAxis;    // 0 = R, 1 = A, 2 = S
};

bool IsSliceView(ViewKind kind);
/// Slice frame of a slice view (undefined for ThreeD).
SliceAxes GetSliceAxes(ViewKind kind);
/// Unit vector from the slice plane towards the camera (X × Y).
void GetCameraDirection(ViewKind kind, double towardsCamera[3]);
const char* GetViewName(ViewKind kind);  // "Axial", "Sagittal", "Coronal", "3D"
/// Slicer's colours: red axial, yellow sagittal, green coronal.
void GetViewColor(ViewKind kind, double rgb[3]);

}  // namespace rp
