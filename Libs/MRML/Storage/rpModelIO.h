#pragma once
// Model files (VTK XML and legacy, STL, PLY, OBJ: ModelFileExtensions()). Points in the files are
// RAS unless the file says otherwise (Slicer's "SPACE=LPS" comment in .vtk/.stl headers, field
// data in .vtp).
#include <string>
#include <vector>

class vtkPolyData;

namespace rp {

/// The model file extensions read and written here (the one list: the storage registry, file
/// dialogs, CLI help and error messages take it from here).
const std::vector<std::string>& ModelFileExtensions();
/// The same list as text for help and messages: ".vtp, .vtk, .stl, .ply, .obj".
std::string ModelFileExtensionsText();

/// `spaceWhenUntagged` ("LPS" or "RAS"): the coordinate system of a file without a SPACE tag
/// (Slicer reads such files as its storage node says: LPS, or RAS in scenes older than 4.11).
bool ReadModelFile(const std::string& path, vtkPolyData* output, std::string& error,
                   const std::string& spaceWhenUntagged = "LPS");
bool WriteModelFile(const std::string& path, vtkPolyData* polyData, std::string& error);

}  // namespace rp
