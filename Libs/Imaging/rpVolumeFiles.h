#pragma once
// One entry point for volume files of every format RoboPlan reads and writes: DICOM series
// (a folder, a DICOMDIR or one .dcm file; DCMTK, in libRoboPlanDicom.so loaded on the first one:
// rpDicomEntries.h) and NRRD / NIfTI / MetaImage (ITK, through rpVolumeIO). Everything is RAS here; the formats' LPS is converted at their boundary.
#include <string>
#include <vector>

#include "rpDicomSeries.h"
#include "rpDicomWriter.h"
#include "rpImageVolume.h"
#include "rpProgress.h"
#include "rpVolumeIO.h"

namespace rp {

struct VolumeReadOptions {
  std::string SeriesInstanceUID;  // DICOM: which series when the folder holds several
  DicomReadOptions Dicom;
};

/// Reads a volume; `volume` is only assigned on success. What `path` is comes from the loader
/// (rp::FindDataReader, rpDataLoader.h): DICOM (or what no reader claims: the DICOM scan says
/// why it is not DICOM) is read as one series, a node file holding an image (IsVolumeFileName)
/// as a volume file; anything else (a model, a scene, a DICOM SEG once RegisterImagingReaders
/// ran) is refused by name.
/// Scenes and nodes: rp::LoadPath.
bool ReadVolume(const std::string& path, ImageVolume& volume, std::string& error,
                const VolumeReadOptions& options = {}, std::vector<std::string>* warnings = nullptr,
                const ProgressCallback& progress = nullptr);

/// Writes a volume: a volume file name → that format; anything else → a DICOM series folder.
bool WriteVolume(const std::string& path, const ImageVolume& volume, std::string& error,
                 const DicomWriteOptions& dicom = {}, const ProgressCallback& progress = nullptr);

}  // namespace rp
