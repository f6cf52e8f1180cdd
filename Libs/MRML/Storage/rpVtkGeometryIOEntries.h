#pragma once
// Internal to RoboPlanMRMLStorage: the entries of libRoboPlanVtkGeometryIO.so (rpVtkGeometryIO.cxx),
// VTK's IOGeometry readers and writers of the model formats STL and OBJ, which rpModelIO.cxx
// loads on the first such file. Their names and types, in one place for both sides. vtkIOGeometry
// brings vtkIOImage (TIFF, JPEG, PNG, WebP...), vtkRenderingCore and vtkFiltersHybrid: about 20
// libraries every command would otherwise map at start-up to read a format few files use.
#include <string>

class vtkPolyData;

namespace rp::geometryio {

constexpr const char* Library = "libRoboPlanVtkGeometryIO.so";

/// roboplan_vtk_read_geometry: an .stl or .obj file's mesh as written (no coordinate change) into
/// `output`; false with `error` naming the file.
using ReadFunction = bool (*)(const std::string& path, vtkPolyData* output, std::string& error);
constexpr const char* ReadEntry = "roboplan_vtk_read_geometry";

/// roboplan_vtk_write_geometry: `mesh` into `target` in the format of `path`'s extension (.stl:
/// binary, triangulated; .obj), `header` as the file's comment; false with `error` why.
using WriteFunction = bool (*)(const std::string& path, const std::string& target, vtkPolyData* mesh,
                               const std::string& header, std::string& error);
constexpr const char* WriteEntry = "roboplan_vtk_write_geometry";

}  // namespace rp::geometryio
