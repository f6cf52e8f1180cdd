#pragma once
// Volume files through ITK's ImageIO (NRRD .nrrd/.nhdr, NIfTI .nii/.nii.gz, MetaImage .mha/.mhd),
// which lives in libRoboPlanItkImageIO.so beside this library, loaded on the first volume file read
// or written (rpItkImageIOEntries.h; without it the error names the file). Files are LPS; the node
// is RAS: the conversion happens there, once.
#include <map>
#include <string>

class vtkImageData;
class vtkMatrix4x4;
class vtkRPImageNode;

namespace rp {

/// Raw image with its geometry in RAS, plus the file's key/value metadata (NRRD `key:=value`).
struct VolumeFileData {
  vtkImageData* Image = nullptr;  // caller-owned output (origin 0, spacing 1)
  vtkMatrix4x4* IJKToRAS = nullptr;  // caller-owned output
  std::map<std::string, std::string> Metadata;
};

/// Reads a 3D scalar volume (2D images load as one slice). Multi-component images are refused.
bool ReadVolumeFile(const std::string& path, VolumeFileData& data, std::string& error);
/// Writes a 3D scalar volume with metadata; NRRD is written gzip-compressed.
bool WriteVolumeFile(const std::string& path, vtkImageData* image, const vtkMatrix4x4* ijkToRAS,
                     const std::map<std::string, std::string>& metadata, std::string& error,
                     bool compress = true);

/// True for names the volume storage reads (its Extensions(), below: .nrrd .nii.gz ...; a .seg.nrrd
/// is one too, as its labelmap). Which reader a path goes to is the loader's answer
/// (rp::FindDataReader); this says whether a node file holds an image.
bool IsVolumeFileName(const std::string& path);

/// Node-level helpers (image + IJKToRAS of a volume or segmentation node).
bool ReadVolumeFile(const std::string& path, vtkRPImageNode* node, std::string& error);
bool WriteVolumeFile(const std::string& path, vtkRPImageNode* node, std::string& error);

}  // namespace rp
