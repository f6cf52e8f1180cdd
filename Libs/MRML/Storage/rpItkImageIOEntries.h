#pragma once
// Internal to RoboPlanMRMLStorage: the entries of libRoboPlanItkImageIO.so (rpItkImageIO.cxx), ITK's
// ImageIO for NRRD, NIfTI and MetaImage, which rpVolumeIO.cxx and rpSegmentationIO.cxx load on the
// first volume or segmentation file read or written. Their names and types, in one place for both
// sides. ITK (ITKCommon, vnl, ImageIO and its NRRD, NIfTI and MetaIO: 14 libraries) is then mapped
// only by a program that reads or writes such a file, not by every command at start-up.
#include <map>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "rpVolumeIO.h"

#define RP_ITK_IMAGE_IO_ENTRY extern "C" __attribute__((visibility("default")))

namespace rp::itkimageio {

constexpr const char* Library = "libRoboPlanItkImageIO.so";

/// roboplan_itk_read_volume: what rp::ReadVolumeFile(path, data, error) does (rpVolumeIO.h).
using ReadVolumeFunction = bool (*)(const std::string& path, VolumeFileData& data, std::string& error);
constexpr const char* ReadVolumeEntry = "roboplan_itk_read_volume";

/// roboplan_itk_write_volume: the volume (RAS) into the file `target` in the format of `path`'s
/// extension (`target` is a temporary name beside `path` when written atomically); false with
/// `error` saying why, without the path.
using WriteVolumeFunction = bool (*)(const std::string& path, const std::string& target, vtkImageData* image,
                                     const vtkMatrix4x4* ijkToRAS, const std::map<std::string, std::string>& metadata,
                                     bool compress, std::string& error);
constexpr const char* WriteVolumeEntry = "roboplan_itk_write_volume";

/// roboplan_itk_read_layers: a 4-D multi-layer .seg.nrrd (ITK sees the "list" axis as pixel
/// components) as one labelmap per layer, its IJK-to-RAS and its key/value fields.
using ReadLayersFunction = bool (*)(const std::string& path, std::vector<vtkSmartPointer<vtkImageData>>& layers,
                                    vtkMatrix4x4* ijkToRAS, std::map<std::string, std::string>& metadata,
                                    std::string& error);
constexpr const char* ReadLayersEntry = "roboplan_itk_read_layers";

/// The entry `symbol` of libRoboPlanItkImageIO.so beside RoboPlanMRMLStorage, loaded on first use
/// (rpVolumeIO.cxx). nullptr with `error` = "'<path>': NRRD, NIfTI and MetaImage are not
/// available: cannot load <library file>: <why>".
void* EntrySymbol(const char* symbol, const std::string& path, std::string& error);

template <typename Function>
Function Entry(const char* symbol, const std::string& path, std::string& error) {
  return reinterpret_cast<Function>(EntrySymbol(symbol, path, error));
}

}  // namespace rp::itkimageio
