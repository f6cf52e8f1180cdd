// libRoboPlanVtkGeometryIO.so: STL and OBJ through VTK's IOGeometry (entries: rpVtkGeometryIOEntries.h),
// loaded by rpModelIO.cxx on the first such file, so that no command maps vtkIOGeometry and what it
// brings (vtkIOImage and its image codecs, vtkRenderingCore, vtkFiltersHybrid) before it needs them.
#include <fstream>
#include <type_traits>

#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkOBJWriter.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>
#include <vtkSTLWriter.h>
#include <vtkTriangleFilter.h>

#include "rpAtomicFile.h"
#include "rpNodeStorage.h"
#include "rpVtkGeometryIOEntries.h"

#define RP_GEOMETRY_IO_ENTRY extern "C" __attribute__((visibility("default")))

RP_GEOMETRY_IO_ENTRY bool roboplan_vtk_read_geometry(const std::string& path, vtkPolyData* output, std::string& error) {
  if (rp::HasExtension(path, ".stl")) {
    vtkNew<vtkSTLReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    if (reader->GetErrorCode() != 0) {
      error = "'" + path + "' is not a readable STL file";
      return false;
    }
    output->ShallowCopy(reader->GetOutput());
    return true;
  }
  if (rp::HasExtension(path, ".obj")) {
    vtkNew<vtkOBJReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    output->ShallowCopy(reader->GetOutput());
    return true;
  }
  error = "'" + path + "' is neither STL nor OBJ";
  return false;
}

RP_GEOMETRY_IO_ENTRY bool roboplan_vtk_write_geometry(const std::string& path, const std::string& target,
                                                      vtkPolyData* mesh, const std::string& header, std::string& error) {
  int ok = 0;
  if (rp::HasExtension(path, ".stl")) {
    vtkNew<vtkTriangleFilter> triangles;
    triangles->SetInputData(mesh);
    vtkNew<vtkSTLWriter> writer;
    writer->SetInputConnection(triangles->GetOutputPort());
    writer->SetFileName(target.c_str());
    writer->SetFileTypeToBinary();
    writer->SetHeader(header.c_str());
    ok = writer->Write();
  } else if (rp::HasExtension(path, ".obj")) {
    vtkNew<vtkOBJWriter> writer;
    writer->SetInputData(mesh);
    writer->SetFileName(target.c_str());
    ok = writer->Write();
    if (ok) {
      // vtkOBJWriter has no comment option: prepend the coordinate system line.
      std::string contents;
      if (!rp::ReadFile(target, contents, error)) return false;
      std::ofstream out(target, std::ios::binary | std::ios::trunc);
      out << "# " << header << "\n" << contents;
      ok = out.good();
    }
  } else {
    error = "'" + path + "' is neither STL nor OBJ";
    return false;
  }
  if (!ok) error = "the VTK writer failed (disk full or no permission?)";
  return ok != 0;
}

// The entries' types are the header's (a compile error here when one side changes).
static_assert(std::is_same_v<decltype(&roboplan_vtk_read_geometry), rp::geometryio::ReadFunction>);
static_assert(std::is_same_v<decltype(&roboplan_vtk_write_geometry), rp::geometryio::WriteFunction>);
