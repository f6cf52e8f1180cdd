#include "rpVolumeIO.h"

#include <vtkNew.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>

#include "rpAtomicFile.h"
#include "rpItkImageIOEntries.h"
#include "rpNodeStorage.h"
#include "rpSiblingLibrary.h"
#include "rpStorageFormats.h"
#include "vtkRPImageNode.h"
#include "vtkRPScalarVolumeNode.h"

namespace rp {

void* itkimageio::EntrySymbol(const char* symbol, const std::string& path, std::string& error) {
  std::string why;
  void* entry = SiblingLibrarySymbol(reinterpret_cast<const void*>(&itkimageio::EntrySymbol), itkimageio::Library,
                                     symbol, why);
  if (!entry) error = "'" + path + "': NRRD, NIfTI and MetaImage are not available: " + why;
  return entry;
}

bool ReadVolumeFile(const std::string& path, VolumeFileData& data, std::string& error) {
  if (!data.Image || !data.IJKToRAS) {
    error = "ReadVolumeFile: no output image or matrix given";
    return false;
  }
  const auto read = itkimageio::Entry<itkimageio::ReadVolumeFunction>(itkimageio::ReadVolumeEntry, path, error);
  return read && read(path, data, error);
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
  std::string why;
  const auto write = itkimageio::Entry<itkimageio::WriteVolumeFunction>(itkimageio::WriteVolumeEntry, path, why);
  if (!write) {
    error = "cannot write " + why;
    return false;
  }
  auto writeTo = [&](const std::string& target, std::string& err) {
    return write(path, target, image, ijkToRAS, metadata, compress, err);
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
