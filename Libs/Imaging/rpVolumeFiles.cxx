#include "rpVolumeFiles.h"

#include <filesystem>

#include "rpDataLoader.h"
#include "rpDicomEntries.h"
#include "rpImagingReaders.h"
#include "rpNodeStorage.h"

namespace rp {

bool ReadVolume(const std::string& path, ImageVolume& volume, std::string& error, const VolumeReadOptions& options,
                std::vector<std::string>* warnings, const ProgressCallback& progress) {
  // What the loader says the path is; no reader (the imaging readers not registered by this
  // program, or a DICOM file without a known extension) is a DICOM read too.
  const DataReader* reader = FindDataReader(path);
  if (!reader || reader == GetDicomDataReader()) {
    const auto read = dicom::Entry<dicom::ReadVolumeFunction>(dicom::ReadVolumeEntry, path, error);
    return read && read(path, volume, error, options.SeriesInstanceUID, options.Dicom, warnings, progress);
  }
  if (!IsVolumeFileName(path)) {
    const NodeStorage* storage = FindNodeStorageForFile(path);
    error = "'" + path + "' is a " + (storage ? storage->Description() : reader->Description()) + " file, not a volume";
    return false;
  }
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    error = "no such volume file: " + path;
    return false;
  }
  ImageVolume result;
  result.Image = vtkSmartPointer<vtkImageData>::New();
  VolumeFileData data;
  data.Image = result.Image;
  data.IJKToRAS = result.IJKToRAS;
  if (!ReadVolumeFile(path, data, error)) return false;
  if (result.Empty()) {
    error = path + ": the volume is empty";
    return false;
  }
  result.Description = std::filesystem::path(path).filename().string();
  if (progress) progress(1.0, "read");
  volume = result;
  return true;
}

bool WriteVolume(const std::string& path, const ImageVolume& volume, std::string& error, const DicomWriteOptions& dicom,
                 const ProgressCallback& progress) {
  if (volume.Empty()) {
    error = "nothing to write: the volume is empty";
    return false;
  }
  if (IsVolumeFileName(path)) {
    const bool ok = WriteVolumeFile(path, volume.Image, volume.IJKToRAS, {}, error);
    if (ok && progress) progress(1.0, "written");
    return ok;
  }
  const auto write = dicom::Entry<dicom::WriteSeriesFunction>(dicom::WriteSeriesEntry, path, error);
  return write && write(volume, path, dicom, error, nullptr, progress);
}

}  // namespace rp
