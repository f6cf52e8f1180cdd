#include "rpDicomReferenceSeries.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dctk.h>

#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include "rpDicomCommon.h"
#include "rpDicomMagic.h"
#include "rpDicomSeries.h"

namespace fs = std::filesystem;

namespace rp {

namespace {

std::string Text(DcmItem* item, const DcmTagKey& tag) {
  OFString value;
  return item->findAndGetOFStringArray(tag, value).good() ? std::string(value.c_str()) : std::string();
}

// 1 SEG, 2 RTSTRUCT, 0 anything else (or not DICOM), from the first elements of the file.
int FileKind(const std::string& path) {
  if (!MaybeDicomFile(path)) return 0;
  DcmFileFormat format;
  // The SOP Class UID is the dataset's first elements: stop right after it (a few hundred bytes).
  if (format.loadFileUntilTag(path.c_str(), EXS_Unknown, EGL_noChange, DCM_MaxReadLength, ERM_autoDetect,
                              DCM_SOPInstanceUID)
          .bad())
    return 0;
  const std::string sopClass = Text(format.getDataset(), DCM_SOPClassUID);
  if (sopClass == UID_SegmentationStorage) return 1;
  if (sopClass == UID_RTStructureSetStorage) return 2;
  return 0;
}

}  // namespace

int DicomSegmentationObjectKind(const std::string& path, std::string* object, std::string* error) {
  InitializeDcmtk();
  std::error_code ec;
  if (!fs::is_directory(path, ec)) {
    const int kind = fs::is_regular_file(path, ec) ? FileKind(path) : 0;
    if (kind && object) *object = path;
    return kind;
  }
  std::vector<std::string> files;
  for (fs::recursive_directory_iterator it(path, fs::directory_options::skip_permission_denied, ec), end;
       !ec && it != end; it.increment(ec))
    if (it->is_regular_file(ec)) files.push_back(it->path().string());
  std::sort(files.begin(), files.end());
  int found = 0;
  std::vector<std::string> objects;
  for (const std::string& file : files) {
    const int kind = FileKind(file);
    if (!kind) continue;
    if (!found) found = kind;
    objects.push_back(file);
  }
  if (objects.size() > 1) {
    if (error) {
      *error = path + " holds " + std::to_string(objects.size()) + " DICOM segmentation objects (" + objects[0] +
               ", " + objects[1] + (objects.size() > 2 ? ", ..." : "") + "): name one file";
    }
    return -1;
  }
  if (found && object) *object = objects.front();
  return found;
}

DicomReferenceSeries DicomReferenceFromVolume(const DicomSeriesInfo& series, const ImageVolume& volume) {
  DicomReferenceSeries reference;
  reference.Volume = volume;
  reference.SeriesInstanceUID = series.SeriesInstanceUID;
  reference.StudyInstanceUID = series.StudyInstanceUID;
  reference.FrameOfReferenceUID = series.FrameOfReferenceUID;
  reference.FirstFile = series.Files.empty() ? std::string() : series.Files.front();
  return reference;
}

bool ReadDicomReferenceSeries(const std::string& path, DicomReferenceSeries& reference, std::string& error,
                              const std::string& seriesUID) {
  InitializeDcmtk();
  DicomScanResult scan;
  if (!ScanDicom(path, scan, error)) return false;
  std::vector<const DicomSeriesInfo*> matches;
  for (const auto& s : scan.Series)
    if (seriesUID.empty() || s.StackID == seriesUID || s.SeriesInstanceUID == seriesUID) matches.push_back(&s);
  if (matches.size() != 1) {
    error = matches.empty() ? "no DICOM image series" + (seriesUID.empty() ? "" : " " + seriesUID) + " in " + path
                            : path + " holds " + std::to_string(matches.size()) +
                                  " image series or stacks: name the referenced one";
    return false;
  }
  const DicomSeriesInfo& series = *matches.front();
  ImageVolume volume;
  if (!ReadDicomSeries(series, volume, error)) return false;
  DicomReferenceSeries result = DicomReferenceFromVolume(series, volume);
  int dims[3];
  result.Volume.Image->GetDimensions(dims);
  result.SOPClassUIDs.assign(dims[2], "");
  result.SOPInstanceUIDs.assign(dims[2], "");
  vtkNew<vtkMatrix4x4> rasToIJK;
  vtkMatrix4x4::Invert(result.Volume.IJKToRAS, rasToIJK);
  for (const std::string& file : series.Files) {
    DcmFileFormat format;
    if (format.loadFileUntilTag(file.c_str(), EXS_Unknown, EGL_noChange, DCM_MaxReadLength, ERM_autoDetect,
                                DCM_FloatPixelData)
            .bad())
      continue;
    DcmDataset* ds = format.getDataset();
    Float64 lps[3];
    bool ok = !ds->tagExists(DCM_NumberOfFrames) || Text(ds, DCM_NumberOfFrames) == "1";
    for (unsigned long a = 0; a < 3 && ok; ++a) ok = ds->findAndGetFloat64(DCM_ImagePositionPatient, lps[a], a).good();
    if (!ok) continue;
    const double ras[4] = {-lps[0], -lps[1], lps[2], 1.0};
    double ijk[4];
    rasToIJK->MultiplyPoint(ras, ijk);
    const long k = std::lround(ijk[2]);
    if (k < 0 || k >= dims[2] || std::abs(ijk[2] - double(k)) > 0.01) continue;
    result.SOPClassUIDs[k] = Text(ds, DCM_SOPClassUID);
    result.SOPInstanceUIDs[k] = Text(ds, DCM_SOPInstanceUID);
  }
  reference = std::move(result);
  return true;
}

}  // namespace rp
