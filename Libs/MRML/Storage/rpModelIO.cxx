#include "rpModelIO.h"

#include <algorithm>
#include <cstdint>
#include <limits>

#include <vtkCellArray.h>
#include <vtkTypeInt32Array.h>
#include <vtkTypeInt64Array.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPLYReader.h>
#include <vtkPLYWriter.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataReader.h>
#include <vtkPolyDataWriter.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkTransform.h>
#include <vtkTransformPolyDataFilter.h>
#include <vtkTriangleFilter.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>

#include <fstream>

#include "rpAtomicFile.h"
#include "rpLPSRAS.h"
#include "rpNodeStorage.h"
#include "rpSiblingLibrary.h"
#include "rpStorageFormats.h"
#include "rpVtkGeometryIOEntries.h"
#include "vtkRPDeflateDataCompressor.h"
#include "vtkRPModelNode.h"

// Coordinate system tag as 3D Slicer writes it: "SPACE=LPS" in the header of .vtk/.stl/.ply/.obj
// files and a "SPACE" string array in the field data of .vtp files. Files without a tag are read
// as LPS, as Slicer does by default.
namespace rp {
namespace {

const char* const SpaceTag = "SPACE";

vtkSmartPointer<vtkPolyData> FlipLPSRAS(vtkPolyData* input) {
  double s[16];
  LPSRASMatrix(s);
  vtkNew<vtkTransform> flip;
  flip->SetMatrix(s);
  vtkNew<vtkTransformPolyDataFilter> filter;
  filter->SetTransform(flip);
  filter->SetInputData(input);
  filter->Update();
  auto output = vtkSmartPointer<vtkPolyData>::New();
  output->ShallowCopy(filter->GetOutput());
  return output;
}

// "RAS", "LPS" or "" (no tag) from free text such as a file header.
std::string SpaceFromText(const std::string& text) {
  const auto at = text.find(std::string(SpaceTag) + "=");
  if (at == std::string::npos) return {};
  const std::string value = text.substr(at + 6, 3);
  return (value == "RAS" || value == "LPS") ? value : std::string();
}

std::string ReadFirstBytes(const std::string& path, size_t count) {
  std::ifstream in(path, std::ios::binary);
  std::string head(count, '\0');
  in.read(&head[0], static_cast<std::streamsize>(count));
  head.resize(static_cast<size_t>(in.gcount()));
  return head;
}

// STL and OBJ are VTK's IOGeometry's, in a library of its own loaded on the first such file
// (rpVtkGeometryIOEntries.h). nullptr with `error` naming the file that did not load.
template <typename Function>
Function GeometryIO(const char* symbol, const std::string& path, std::string& error) {
  std::string why;
  const auto function = SiblingLibraryFunction<Function>(reinterpret_cast<const void*>(&ReadFirstBytes),
                                                         geometryio::Library, symbol, why);
  if (!function) error = "'" + path + "': STL and OBJ are not available: " + why;
  return function;
}

bool IsVtkGeometryFile(const std::string& path) { return HasExtension(path, ".stl") || HasExtension(path, ".obj"); }

}  // namespace

const std::vector<std::string>& ModelFileExtensions() {
  static const std::vector<std::string> extensions = {".vtp", ".vtk", ".stl", ".ply", ".obj"};
  return extensions;
}

std::string ModelFileExtensionsText() {
  std::string text;
  for (const std::string& extension : ModelFileExtensions()) text += (text.empty() ? "" : ", ") + extension;
  return text;
}

bool ReadModelFile(const std::string& path, vtkPolyData* output, std::string& error,
                   const std::string& spaceWhenUntagged) {
  if (!std::ifstream(path).good()) {
    error = "cannot open model file '" + path + "'";
    return false;
  }
  vtkSmartPointer<vtkPolyData> mesh;
  std::string space;
  if (HasExtension(path, ".vtp")) {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName(path.c_str());
    if (!reader->CanReadFile(path.c_str())) {
      error = "'" + path + "' is not a VTK XML PolyData file";
      return false;
    }
    reader->Update();
    if (reader->GetErrorCode() != 0) {
      error = "'" + path + "' is corrupt (VTK XML reader failed)";
      return false;
    }
    mesh = reader->GetOutput();
    if (auto* tag = vtkStringArray::SafeDownCast(mesh->GetFieldData()->GetAbstractArray(SpaceTag))) {
      if (tag->GetNumberOfValues() > 0) space = tag->GetValue(0);
    }
  } else if (HasExtension(path, ".vtk")) {
    vtkNew<vtkPolyDataReader> reader;
    reader->SetFileName(path.c_str());
    if (!reader->IsFilePolyData()) {
      error = "'" + path + "' is not a legacy VTK polydata file";
      return false;
    }
    reader->Update();
    mesh = reader->GetOutput();
    if (reader->GetHeader()) space = SpaceFromText(reader->GetHeader());
  } else if (IsVtkGeometryFile(path)) {
    const auto read = GeometryIO<geometryio::ReadFunction>(geometryio::ReadEntry, path, error);
    mesh = vtkSmartPointer<vtkPolyData>::New();
    if (!read || !read(path, mesh, error)) return false;
    space = SpaceFromText(ReadFirstBytes(path, HasExtension(path, ".stl") ? 80 : 1024));
  } else if (HasExtension(path, ".ply")) {
    vtkNew<vtkPLYReader> reader;
    if (!reader->CanReadFile(path.c_str())) {
      error = "'" + path + "' is not a PLY file";
      return false;
    }
    reader->SetFileName(path.c_str());
    reader->Update();
    mesh = reader->GetOutput();
    space = SpaceFromText(ReadFirstBytes(path, 1024));
  } else {
    error = "'" + path + "': unknown model extension (use " + ModelFileExtensionsText() + ")";
    return false;
  }
  if (!mesh || mesh->GetNumberOfPoints() == 0) {
    error = "'" + path + "' holds no points (empty or corrupt model file)";
    return false;
  }
  vtkSmartPointer<vtkPolyData> ras = ((space.empty() ? spaceWhenUntagged : space) == "RAS") ? mesh : FlipLPSRAS(mesh);
  ras->GetFieldData()->RemoveArray(SpaceTag);
  output->ShallowCopy(ras);
  return true;
}

namespace {
// The cells with 32-bit connectivity and offsets when the ids fit (the writer then writes Int32
// arrays, which every VTK XML reader, Slicer's included, reads as it reads Int64): half the cell
// bytes to compress and store. New cell arrays: the input's may be shared with a model.
void WithInt32Cells(vtkPolyData* mesh) {
  constexpr vtkIdType int32Max = std::numeric_limits<int32_t>::max();
  if (mesh->GetNumberOfPoints() >= int32Max) return;
  auto convert = [&](vtkCellArray* cells) -> vtkSmartPointer<vtkCellArray> {
    if (!cells || !cells->IsStorage64Bit() || cells->GetNumberOfConnectivityIds() >= int32Max) return cells;
    vtkNew<vtkTypeInt32Array> offsets, connectivity;
    vtkTypeInt64Array* offsets64 = cells->GetOffsetsArray64();
    vtkTypeInt64Array* connectivity64 = cells->GetConnectivityArray64();
    offsets->SetNumberOfValues(offsets64->GetNumberOfValues());
    connectivity->SetNumberOfValues(connectivity64->GetNumberOfValues());
    std::copy(offsets64->GetPointer(0), offsets64->GetPointer(0) + offsets64->GetNumberOfValues(),
              offsets->GetPointer(0));
    std::copy(connectivity64->GetPointer(0), connectivity64->GetPointer(0) + connectivity64->GetNumberOfValues(),
              connectivity->GetPointer(0));
    auto converted = vtkSmartPointer<vtkCellArray>::New();
    converted->SetData(offsets, connectivity);
    return converted;
  };
  mesh->SetVerts(convert(mesh->GetVerts()));
  mesh->SetLines(convert(mesh->GetLines()));
  mesh->SetPolys(convert(mesh->GetPolys()));
  mesh->SetStrips(convert(mesh->GetStrips()));
}
}  // namespace

bool WriteModelFile(const std::string& path, vtkPolyData* polyData, std::string& error) {
  if (!polyData || polyData->GetNumberOfPoints() == 0) {
    error = "cannot write '" + path + "': the model has no points";
    return false;
  }
  vtkSmartPointer<vtkPolyData> lps = FlipLPSRAS(polyData);
  const std::string header = "RoboPlan output. SPACE=LPS";
  const auto writeGeometry = IsVtkGeometryFile(path)
                                 ? GeometryIO<geometryio::WriteFunction>(geometryio::WriteEntry, path, error)
                                 : nullptr;
  if (IsVtkGeometryFile(path) && !writeGeometry) return false;
  auto writeTo = [&](const std::string& target, std::string& err) -> bool {
    int ok = 0;
    if (HasExtension(path, ".vtp")) {
      vtkNew<vtkStringArray> tag;
      tag->SetName(SpaceTag);
      tag->InsertNextValue("LPS");
      lps->GetFieldData()->AddArray(tag);
      vtkNew<vtkXMLPolyDataWriter> writer;
      writer->SetInputData(lps);
      writer->SetFileName(target.c_str());
      // Raw appended data (not base64: a third larger and, through one stream write per 3 bytes,
      // slower than compressing), zlib streams made by libdeflate at level 1: files 25 % smaller
      // and written about 4 times as fast as with zlib at level 1 in base64.
      writer->SetDataModeToAppended();
      writer->EncodeAppendedDataOff();
      vtkNew<vtkRPDeflateDataCompressor> compressor;
      writer->SetCompressor(compressor);
      writer->SetCompressionLevel(1);
      WithInt32Cells(lps);
      ok = writer->Write();
    } else if (HasExtension(path, ".vtk")) {
      vtkNew<vtkPolyDataWriter> writer;
      writer->SetInputData(lps);
      writer->SetFileName(target.c_str());
      writer->SetFileVersion(42);  // readable by older VTK and most other software
      writer->SetFileTypeToBinary();
      writer->SetHeader(header.c_str());
      ok = writer->Write();
    } else if (HasExtension(path, ".ply")) {
      vtkNew<vtkTriangleFilter> triangles;
      triangles->SetInputData(lps);
      vtkNew<vtkPLYWriter> writer;
      writer->SetInputConnection(triangles->GetOutputPort());
      writer->SetFileName(target.c_str());
      writer->SetFileTypeToBinary();
      writer->AddComment("SPACE=LPS");
      ok = writer->Write();
    } else if (writeGeometry) {
      return writeGeometry(path, target, lps, header, err);
    } else {
      err = "unknown model extension (use " + ModelFileExtensionsText() + ")";
      return false;
    }
    if (!ok) err = "the VTK writer failed (disk full or no permission?)";
    return ok != 0;
  };
  return WriteAtomicallyWith(path, writeTo, error);
}

namespace {
class ModelStorage : public NodeStorage {
 public:
  std::string Description() const override { return "model (VTP/VTK/STL/PLY/OBJ)"; }
  bool CanHandle(const vtkRPNode* node) const override {
    return node && const_cast<vtkRPNode*>(node)->IsA("vtkRPModelNode");
  }
  std::vector<std::string> Extensions() const override { return ModelFileExtensions(); }
  std::string NodeClassForFiles() const override { return "vtkRPModelNode"; }
  bool Write(vtkRPNode* node, const std::string& path, std::string& error) const override {
    return WriteModelFile(path, vtkRPModelNode::SafeDownCast(node)->GetPolyData(), error);
  }
  bool Read(vtkRPNode* node, const std::string& path, std::string& error) const override {
    auto mesh = vtkSmartPointer<vtkPolyData>::New();
    if (!ReadModelFile(path, mesh, error)) return false;
    vtkRPModelNode::SafeDownCast(node)->SetPolyData(mesh);
    return true;
  }
};
}  // namespace

std::shared_ptr<NodeStorage> MakeModelStorage() { return std::make_shared<ModelStorage>(); }

}  // namespace rp
