// libRoboPlanItkImageIO.so: NRRD, NIfTI and MetaImage volumes and the layers of a .seg.nrrd through
// ITK's ImageIO (entries: rpItkImageIOEntries.h), loaded by rpVolumeIO.cxx and rpSegmentationIO.cxx
// on the first such file read or written, so that no command maps ITK (14 libraries: ITKCommon,
// vnl, the IO and its NRRD, NIfTI and MetaIO readers) before it reads or writes a volume.
// Files are LPS, the interface RAS: the conversion happens here, once.
#include <cmath>
#include <type_traits>

#include <itkImageIOBase.h>
#include <itkMetaDataObject.h>
#include <itkMetaImageIO.h>
#include <itkNiftiImageIO.h>
#include <itkNrrdImageIO.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>

#include "rpItkImageIOEntries.h"
#include "rpLPSRAS.h"
#include "rpMemoryBudget.h"
#include "rpNodeStorage.h"
#include "rpNrrdGzipVoxels.h"

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

// The string entries of an ITK image IO's dictionary (NRRD `key:=value`), as files carry them.
std::map<std::string, std::string> StringMetadata(const itk::MetaDataDictionary& dictionary) {
  std::map<std::string, std::string> metadata;
  for (const auto& key : dictionary.GetKeys()) {
    std::string value;
    if (itk::ExposeMetaData<std::string>(dictionary, key, value)) metadata[key] = value;
  }
  return metadata;
}

// `read()`, with what ITK (or the standard library) throws as `error` naming the file.
template <typename Read>
bool WithFileErrors(const std::string& path, std::string& error, const Read& read) {
  try {
    return read();
  } catch (const itk::ExceptionObject& e) {
    error = "'" + path + "': " + e.GetDescription();
  } catch (const std::exception& e) {
    error = "'" + path + "': " + e.what();
  }
  return false;
}

// rp::ReadVolumeFile's work (rpVolumeIO.h); `data` has its image and matrix (checked there).
bool ReadVolume(const std::string& path, VolumeFileData& data, std::string& error) {
  itk::ImageIOBase::Pointer io = CreateImageIO(path);
  if (!io) {
    error = "'" + path + "': not a volume file this program reads (.nrrd, .nhdr, .nii, .nii.gz, .mha, .mhd)";
    return false;
  }
  return WithFileErrors(path, error, [&] {
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
  });
}

// The volume into `target` in the format of `path`'s extension; false with `err` why.
bool WriteVolume(const std::string& path, const std::string& target, vtkImageData* image, const vtkMatrix4x4* ijkToRAS,
                 const std::map<std::string, std::string>& metadata, bool compress, std::string& err) {
  itk::IOComponentEnum componentType;
  if (!ToITKType(image->GetScalarType(), componentType)) {
    err = std::string("unsupported voxel type ") + image->GetScalarTypeAsString();
    return false;
  }
  itk::ImageIOBase::Pointer io = CreateImageIO(path);
  if (!io) {
    err = "unknown volume extension (use .nrrd, .nii, .nii.gz, .mha)";
    return false;
  }
  int dims[3];
  image->GetDimensions(dims);
  vtkNew<vtkMatrix4x4> ijkToLPS;
  ijkToLPS->DeepCopy(ijkToRAS);
  FlipLPSRAS(ijkToLPS);
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
}

// Reads a 4-D multi-layer file (ITK sees the "list" axis as pixel components) into one labelmap
// per layer.
bool ReadLayers(const std::string& path, std::vector<vtkSmartPointer<vtkImageData>>& layers, vtkMatrix4x4* ijkToRAS,
                std::map<std::string, std::string>& metadata, std::string& error) {
  return WithFileErrors(path, error, [&] {
    auto io = itk::NrrdImageIO::New();
    if (!io->CanReadFile(path.c_str())) {
      error = "'" + path + "': cannot be read as NRRD";
      return false;
    }
    io->SetFileName(path);
    io->ReadImageInformation();
    const unsigned int dimension = io->GetNumberOfDimensions();
    const unsigned int components = io->GetNumberOfComponents();
    if (dimension != 3 || components < 1) {
      error = "'" + path + "': a segmentation must be a 3-D labelmap or a 4-D list of labelmaps";
      return false;
    }
    int vtkType = -1;
    switch (io->GetComponentType()) {
      case itk::IOComponentEnum::UCHAR: vtkType = VTK_UNSIGNED_CHAR; break;
      case itk::IOComponentEnum::CHAR: vtkType = VTK_SIGNED_CHAR; break;
      case itk::IOComponentEnum::USHORT: vtkType = VTK_UNSIGNED_SHORT; break;
      case itk::IOComponentEnum::SHORT: vtkType = VTK_SHORT; break;
      case itk::IOComponentEnum::UINT: vtkType = VTK_UNSIGNED_INT; break;
      case itk::IOComponentEnum::INT: vtkType = VTK_INT; break;
      default:
        error = "'" + path + "': labelmap voxels must be 8-, 16- or 32-bit integers, not " +
                io->GetComponentTypeAsString(io->GetComponentType());
        return false;
    }
    int dims[3];
    vtkNew<vtkMatrix4x4> ijkToLPS;
    for (unsigned int axis = 0; axis < 3; ++axis) {
      dims[axis] = static_cast<int>(io->GetDimensions(axis));
      const std::vector<double> direction = io->GetDirection(axis);
      for (unsigned int row = 0; row < 3; ++row) {
        ijkToLPS->SetElement(static_cast<int>(row), static_cast<int>(axis),
                             direction.at(row) * io->GetSpacing(axis));
      }
      ijkToLPS->SetElement(static_cast<int>(axis), 3, io->GetOrigin(axis));
    }
    // The interleaved file and its layers are both held while splitting: refuse what cannot fit
    // from the header alone, rather than as std::bad_alloc inside VTK.
    const int64_t size[3] = {int64_t(io->GetDimensions(0)), int64_t(io->GetDimensions(1)), int64_t(io->GetDimensions(2))};
    if (!CheckImageFitsInMemory(size, double(io->GetComponentSize()) * components, "'" + path + "'", error, 2.0))
      return false;
    vtkNew<vtkImageData> interleaved;
    interleaved->SetDimensions(dims);
    interleaved->AllocateScalars(vtkType, static_cast<int>(components));
    itk::ImageIORegion region(3);
    for (unsigned int axis = 0; axis < 3; ++axis) {
      region.SetIndex(axis, 0);
      region.SetSize(axis, static_cast<itk::SizeValueType>(dims[axis]));
    }
    io->SetIORegion(region);
    io->Read(interleaved->GetScalarPointer());
    layers.clear();
    const vtkIdType count = interleaved->GetNumberOfPoints();
    vtkDataArray* source = interleaved->GetPointData()->GetScalars();
    for (unsigned int c = 0; c < components; ++c) {
      auto layer = vtkSmartPointer<vtkImageData>::New();
      layer->SetDimensions(dims);
      layer->AllocateScalars(vtkType, 1);
      vtkDataArray* target = layer->GetPointData()->GetScalars();
      for (vtkIdType n = 0; n < count; ++n) target->SetComponent(n, 0, source->GetComponent(n, static_cast<int>(c)));
      layers.push_back(layer);
    }
    metadata = StringMetadata(io->GetMetaDataDictionary());
    FlipLPSRASIndexToSpace(ijkToLPS->GetData());
    ijkToRAS->DeepCopy(ijkToLPS);
    return true;
  });
}

}  // namespace
}  // namespace rp

RP_ITK_IMAGE_IO_ENTRY bool roboplan_itk_read_volume(const std::string& path, rp::VolumeFileData& data, std::string& error) {
  return rp::ReadVolume(path, data, error);
}

RP_ITK_IMAGE_IO_ENTRY bool roboplan_itk_write_volume(const std::string& path, const std::string& target, vtkImageData* image,
                                                     const vtkMatrix4x4* ijkToRAS,
                                                     const std::map<std::string, std::string>& metadata, bool compress,
                                                     std::string& error) {
  return rp::WriteVolume(path, target, image, ijkToRAS, metadata, compress, error);
}

RP_ITK_IMAGE_IO_ENTRY bool roboplan_itk_read_layers(const std::string& path,
                                                    std::vector<vtkSmartPointer<vtkImageData>>& layers,
                                                    vtkMatrix4x4* ijkToRAS, std::map<std::string, std::string>& metadata,
                                                    std::string& error) {
  return rp::ReadLayers(path, layers, ijkToRAS, metadata, error);
}

// The entries' types are the header's (a compile error here when one side changes).
static_assert(std::is_same_v<decltype(&roboplan_itk_read_volume), rp::itkimageio::ReadVolumeFunction>);
static_assert(std::is_same_v<decltype(&roboplan_itk_write_volume), rp::itkimageio::WriteVolumeFunction>);
static_assert(std::is_same_v<decltype(&roboplan_itk_read_layers), rp::itkimageio::ReadLayersFunction>);
