#pragma once
// Linear transform files in ITK's formats (.tfm / .txt text, .h5 where ITK's HDF5 transform IO
// is available), with the convention 3D Slicer uses so its files open here and ours in Slicer:
// the file holds the "from parent" (resampling) transform in LPS. The node holds "to parent"
// in RAS. Conversion: toParentRAS = inverse(S · fromParentLPS · S), S = diag(-1, -1, 1, 1).
#include <string>

class vtkMatrix4x4;

namespace rp {

bool WriteTransformFile(const std::string& path, const vtkMatrix4x4* toParentRAS, std::string& error);
bool ReadTransformFile(const std::string& path, vtkMatrix4x4* toParentRAS, std::string& error);

}  // namespace rp
