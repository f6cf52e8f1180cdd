#pragma once
// The viewer's four views. Each slice view shows a slice node of the scene (vtkRPSliceNode, where
// the slice frames are defined): Axial ↔ "Red", Sagittal ↔ "Yellow", Coronal ↔ "Green", as in
// Slicer's default layout.
#include <string>

namespace rp {

enum class ViewKind { Axial = 0, Sagittal = 1, Coronal = 2, ThreeD = 3 };

bool IsSliceView(ViewKind kind);
const char* GetViewName(ViewKind kind);  // "Axial", "Sagittal", "Coronal", "3D"
/// Slicer's colours: red axial, yellow sagittal, green coronal.
void GetViewColor(ViewKind kind, double rgb[3]);

}  // namespace rp
