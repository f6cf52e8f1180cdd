#pragma once
// Model files: .vtp, .vtk (legacy), .stl, .ply, .obj. Points in the files are RAS unless the
// file says otherwise (Slicer's "SPACE=LPS" comment in .vtk/.stl headers, field data in .vtp).
#include <string>

class vtkPolyData;

namespace rp {

bool ReadModelFile(const std::string& path, vtkPolyData* output, std::string& error);
bool WriteModelFile(const std::string& path, vtkPolyData* polyData, std::string& error);

}  // namespace rp
