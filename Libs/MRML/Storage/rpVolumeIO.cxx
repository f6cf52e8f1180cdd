#include "rpVolumeIO.h"

#include <cmath>

#include <itkImageIOBase.h>
#include <itkMetaDataObject.h>
#include <itkMetaImageIO.h>
#include <itkNiftiImageIO.h>
#include <itkNrrdImageIO.h>
#include <vtkNew.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>

#include "rpAtomicFile.h"
#include "rpLPSRAS.h"
#include "rpMemoryBudget.h"
#include "rpNodeStorage.h"
#include "rpStorageFormats.h"
#include "rpNrrdGzipVoxels.h"
#include "vtkRPImageNode.h"
#include "vtkRPScalarVolumeNode.h"

namespace rp {
namespace {

itk::ImageIOBase::Pointer CreateImageIO(const std::string& path) {
  if (HasExtension(path, ".nrrd") || HasExtension(path, ".nhdr")) return itk::NrrdImageIO::New().GetPointer();
  if (HasExtension(path, ".nii") || HasExtension(path, ".nii.gz")) return itk::NiftiImageIO::New().GetPointer();
  if (HasExtension(path, ".mha") || HasExtension(path, ".mhd")) return itk::MetaImageIO::New().GetPointer();
  return nullptr;
}

int ToVTKType(itk::IOComponentEnum type) {
  switch (type) {
    case itk::IOComponentEnum::UCHAR: return VTK_UNSIGNED_CHAR;
    case itk::IOComponentEnum::CHAR: return VTK_SIGNED_CHAR;
    case itk::IOComponentEnum::USHORT: return VTK_UNSIGNED_SHORT;
    case itk::IOComponentEnum::SHORT: return VTK_SHORT;
    case itk::IOComponentEnum::UINT: return VTK_UNSIGNED_INT;
    case itk::IOComponentEnum::INT: return VTK_INT;
    case itk::IOComponentEnum::ULONG: return VTK_UNSIGNED_LONG;
    case itk::IOComponentEnum::LONG: return VTK_LONG;
    case itk::IOComponentEnum::ULONGLONG: return VTK_UNSIGNED_LONG_LONG;
    case itk::IOComponentEnum::LONGLONG: return VTK_LONG_LONG;
    case itk::IOComponentEnum::FLOAT: return VTK_FLOAT;
    case itk::IOComponentEnum::DOUBLE: return VTK_DOUBLE;
    default: return -1;
  }
}

bool ToITKType(int vtkType, itk::IOComponentEnum& type) {
  switch (vtkType) {
    case VTK_UNSIGNED_CHAR: type = itk::IOComponentEnum::UCHAR; return true;
    case VTK_SIGNED_CHAR:
    case VTK_CHAR: type = itk::IOComponentEnum::CHAR; return true;
    case VTK_UNSIGNED_SHORT: type = itk::IOComponentEnum::USHORT; return true;
    case VTK_SHORT: type = itk::IOComponentEnum::SHORT; return true;
    case VTK_UNSIGNED_INT: type = itk::IOComponentEnum::UINT; return true;
    case VTK_INT: type = itk::IOComponentEnum::INT; return true;
    case VTK_UNSIGNED_LONG: type = itk::IOComponentEnum::ULONG; return true;
    case VTK_LONG: type = itk::IOComponentEnum::LONG; return true;
    case VTK_UNSIGNED_LONG_LONG: type = itk::IOComponentEnum::ULONGLONG; return true;
    case VTK_LONG_LONG: type = itk::IOComponentEnum::LONGLONG; return true;
    case VTK_FLOAT: type = itk::IOComponentEnum::FLOAT; return true;
    case VTK_DOUBLE: type = itk::IOComponentEnum::DOUBLE; return true;
    default: return false;
  }
}

void FlipLPSRAS(vtkMatrix4x4* m) {
  FlipLPSRASIndexToSpace(m->GetData());
  m->Modified();
}

}  // namespace

bool ReadVolumeFile(const std::string& path, VolumeFileData& data, std::string& error) {
  if (!data.Image || !data.IJKToRAS) {
    error = "ReadVolumeFile: no output image or matrix given";
    return false;
  }
  itk::ImageIOBase::Pointer io = CreateImageIO(path);
  if (!io) {
    error = "'" + path + "': not a volume file this program reads (.nrrd, .nhdr, .nii, .nii.gz, .mha, .mhd)";
    return false;
  }
  try {
    if (!io->CanReadFile(path.c_str())) {
      error = "'" + path + "': cannot be read as " + io->GetNameOfClass() + " (missing, unreadable or not that format)";
      return false;
    }
    io->SetFileName(path);
    io->ReadImageInformation();
    const unsigned int dimension = io->GetNumberOfDimensions();
    if (dimension < 2 || dimension > 3) {
      error = "'" + path + "': " + std::to_string(dimension) + "-D image; only 2-D and 3-D scalar volumes are supported";
      return false;
    }
    if (io->GetNumberOfComponents() != 1) {
      error = "'" + path + "': " + std::to_string(io->GetNumberOfComponents()) +
              " components per voxel; only scalar volumes are supported";
      return false;
    }
    const int vtkType = ToVTKType(io->GetComponentType());
    if (vtkType < 0) {
      error = "'" + path + "': unsupported voxel type " + io->GetComponentTypeAsString(io->GetComponentType());
      return false;
    }
    int dims[3] = {1, 1, 1};
    vtkNew<vtkMatrix4x4> ijkToLPS;
    for (unsigned int axis = 0; axis < dimension; ++axis) {
      dims[axis] = static_cast<int>(io->GetDimensions(axis));
      const std::vector<double> direction = io->GetDirection(axis);
      for (unsigned int row = 0; row < 3; ++row) {
        const double d = row < direction.size() ? direction[row] : (row == axis ? 1.0 : 0.0);
        ijkToLPS->SetElement(static_cast<int>(row), static_cast<int>(axis), d * io->GetSpacing(axis));
      }
      ijkToLPS->SetElement(static_cast<int>(axis), 3, io->GetOrigin(axis));
    }
    // Refused here, from the header alone, rather than as std::bad_alloc inside VTK.
    const int64_t size[3] = {int64_t(io->GetDimensions(0)), dimension > 1 ? int64_t(io->GetDimensions(1)) : 1,
                             dimension > 2 ? int64_t(io->GetDimensions(2)) : 1};
    if (!CheckImageFitsInMemory(size, double(io->GetComponentSize()), "'" + path + "'", error)) return false;
    auto image = vtkSmartPointer<vtkImageData>::New();
    image->SetDimensions(dims);
    image->AllocateScalars(vtkType, 1);
    itk::ImageIORegion region(dimension);
    for (unsigned int axis = 0; axis < dimension; ++axis) {
      region.SetIndex(axis, 0);
      region.SetSize(axis, static_cast<itk::SizeValueType>(dims[axis]));
    }
    io->SetIORegion(region);
    const size_t bytes = static_cast<size_t>(size[0] * size[1] * size[2]) * io->GetComponentSize();
    if (!HasExtension(path, ".nrrd") ||
        !ReadNrrdGzipVoxels(path, image->GetScalarPointer(), bytes, io->GetComponentSize()))
      io->Read(image->GetScalarPointer());

    FlipLPSRAS(ijkToLPS);
    data.Image->ShallowCopy(image);
    data.IJKToRAS->DeepCopy(ijkToLPS);
    data.Metadata = StringMetadata(io->GetMetaDataDictionary());
    return true;
  } catch (const itk::ExceptionObject& e) {
    error = "'" + path + "': " + e.GetDescription();
  } catch (const std::exception& e) {
    error = "'" + path + "': " + e.what();
  }
  return false;
}

bool WriteVolumeFile(const std::string& path, vtkImageData* image, const vtkMatrix4x4* ijkToRAS,
                     const std::map<std::string, std::string>& metadata, std::string& error, bool compress) {
  if (!image || !image->GetPointData()->GetScalars()) {
    error = "cannot write '" + path + "': the volume has no image data";
    return false;
  }
  if (image->GetNumberOfScalarComponents() != 1) {
    error = "cannot write '" + path + "': only scalar volumes are supported";
    return false;
  }
  itk::IOComponentEnum componentType;
  if (!ToITKType(image->GetScalarType(), componentType)) {
    error = std::string("cannot write '") + path + "': unsupported voxel type " + image->GetScalarTypeAsString();
    return false;
  }
  if (!CreateImageIO(path)) {
    error = "cannot write '" + path + "': unknown volume extension (use .nrrd, .nii, .nii.gz, .mha)";
    return false;
  }
  int dims[3];
  image->GetDimensions(dims);
  vtkNew<vtkMatrix4x4> ijkToLPS;
  ijkToLPS->DeepCopy(ijkToRAS);
  FlipLPSRAS(ijkToLPS);

  auto writeTo = [&](const std::string& target, std::string& err) {
    itk::ImageIOBase::Pointer io = CreateImageIO(path);
    try {
      io->SetNumberOfDimensions(3);
      io->SetPixelType(itk::IOPixelEnum::SCALAR);
      io->SetComponentType(componentType);
      io->SetNumberOfComponents(1);
      itk::ImageIORegion region(3);
      for (unsigned int axis = 0; axis < 3; ++axis) {
        io->SetDimensions(axis, static_cast<unsigned int>(dims[axis]));
        double spacing = 0;
        for (int row = 0; row < 3; ++row) spacing += std::pow(ijkToLPS->GetElement(row, static_cast<int>(axis)), 2);
        spacing = std::sqrt(spacing);
        if (spacing <= 0) {
          err = "degenerate IJK-to-RAS matrix (zero spacing on axis " + std::to_string(axis) + ")";
          return false;
        }
        io->SetSpacing(axis, spacing);
        io->SetOrigin(axis, ijkToLPS->GetElement(static_cast<int>(axis), 3));
        std::vector<double> direction(3);
        for (int row = 0; row < 3; ++row) direction[static_cast<size_t>(row)] = ijkToLPS->GetElement(row, static_cast<int>(axis)) / spacing;
        io->SetDirection(axis, direction);
        region.SetIndex(axis, 0);
        region.SetSize(axis, static_cast<itk::SizeValueType>(dims[axis]));
      }
      io->SetIORegion(region);
      io->SetUseCompression(compress);
      itk::MetaDataDictionary& dictionary = io->GetMetaDataDictionary();
      for (const auto& [key, value] : metadata) itk::EncapsulateMetaData<std::string>(dictionary, key, value);
      io->SetFileName(target);
      io->Write(image->GetScalarPointer());
      return true;
    } catch (const itk::ExceptionObject& e) {
      err = e.GetDescription();
    }
    return false;
  };
  // A detached header (.nhdr) names its data file, so it cannot be written under a temporary name.
  if (HasExtension(path, ".nhdr") || HasExtension(path, ".mhd")) {
    std::string err;
    if (!writeTo(path, err)) {
      error = "cannot write '" + path + "': " + err;
      return false;
    }
    return true;
  }
  return WriteAtomicallyWith(path, writeTo, error);
}

std::map<std::string, std::string> StringMetadata(const itk::MetaDataDictionary& dictionary) {
  std::map<std::string, std::string> metadata;
  for (const auto& key : dictionary.GetKeys()) {
    std::string value;
    if (itk::ExposeMetaData<std::string>(dictionary, key, value)) metadata[key] = value;
  }
  return metadata;
}

bool IsVolumeFileName(const std::string& path) {
  // The extensions the volume storage lists (ScalarVolumeStorage below): listed there only.
  for (const std::string& ext : ExtensionsForNodeClass("vtkRPScalarVolumeNode")) {
    if (path.size() > ext.size() && HasExtension(path, ext)) return true;
  }
  return false;
}

bool ReadVolumeFile(const std::string& path, vtkRPImageNode* node, std::string& error) {
  auto image = vtkSmartPointer<vtkImageData>::New();
  vtkNew<vtkMatrix4x4> ijkToRAS;
  VolumeFileData data;
  data.Image = image;
  data.IJKToRAS = ijkToRAS;
  if (!ReadVolumeFile(path, data, error)) return false;
  const int previous = node->StartModify();
  node->SetImageData(image);
  node->SetIJKToRASMatrix(ijkToRAS);
  node->EndModify(previous);
  return true;
}

bool WriteVolumeFile(const std::string& path, vtkRPImageNode* node, std::string& error) {
  return WriteVolumeFile(path, node->GetImageData(), node->GetIJKToRASMatrix(), {}, error);
}

namespace {
class ScalarVolumeStorage : public NodeStorage {
 public:
  std::string Description() const override { return "volume (NRRD/NIfTI/MetaImage)"; }
  bool CanHandle(const vtkRPNode* node) const override {
    return node && const_cast<vtkRPNode*>(node)->IsA("vtkRPScalarVolumeNode");
  }
  std::vector<std::string> Extensions() const override {
    return {".nrrd", ".nii.gz", ".nhdr", ".nii", ".mha", ".mhd"};
  }
  std::string NodeClassForFiles() const override { return "vtkRPScalarVolumeNode"; }
  bool Write(vtkRPNode* node, const std::string& path, std::string& error) const override {
    return WriteVolumeFile(path, vtkRPImageNode::SafeDownCast(node), error);
  }
  bool Read(vtkRPNode* node, const std::string& path, std::string& error) const override {
    return ReadVolumeFile(path, vtkRPImageNode::SafeDownCast(node), error);
  }
};
}  // namespace

std::shared_ptr<NodeStorage> MakeScalarVolumeStorage() { return std::make_shared<ScalarVolumeStorage>(); }

}  // namespace rp
