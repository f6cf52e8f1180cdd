// Scanning a folder, a DICOMDIR or a file for DICOM image series (rpDicomSeries.h: ScanDicom):
// every file's header, grouped by SeriesInstanceUID and split into stacks.
#include <algorithm>
#include <climits>
#include <filesystem>
#include <map>

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcdicdir.h>
#include <dcmtk/dcmdata/dctk.h>

#include "rpDicomCommon.h"
#include "rpDicomGeometry.h"
#include "rpDicomHeader.h"
#include "rpDicomSeries.h"

namespace fs = std::filesystem;

namespace rp {

namespace {

using namespace dicom;

// The image files a DICOMDIR names (relative to its folder).
bool DicomDirFiles(const std::string& path, std::vector<std::string>& files, std::string& error) {
  DcmDicomDir dir(path.c_str());
  if (dir.error().bad()) {
    error = "cannot read DICOMDIR " + path + ": " + dir.error().text();
    return false;
  }
  const fs::path base = fs::path(path).parent_path();
  std::vector<DcmDirectoryRecord*> stack = {&dir.getRootRecord()};
  while (!stack.empty()) {
    DcmDirectoryRecord* record = stack.back();
    stack.pop_back();
    for (unsigned long i = 0; i < record->cardSub(); ++i) {
      DcmDirectoryRecord* sub = record->getSub(i);
      if (!sub) continue;
      const std::string id = GetString(sub, DCM_ReferencedFileID);
      if (!id.empty()) {
        std::string relative = id;
        std::replace(relative.begin(), relative.end(), '\\', '/');
        files.push_back((base / relative).string());
      }
      stack.push_back(sub);
    }
  }
  return true;
}

// The files to examine: a folder's (recursively, sorted), a DICOMDIR's images, or the file itself.
bool ListFiles(const std::string& path, std::vector<std::string>& files, std::string& error) {
  std::error_code ec;
  const fs::path root(path);
  if (fs::is_directory(root, ec)) {
    for (fs::recursive_directory_iterator it(root, fs::directory_options::skip_permission_denied, ec), end;
         !ec && it != end; it.increment(ec)) {
      if (it->is_regular_file(ec)) files.push_back(it->path().string());
    }
    if (ec) {
      error = "cannot list folder " + path + ": " + ec.message();
      return false;
    }
    std::sort(files.begin(), files.end());
    return true;
  }
  if (!fs::is_regular_file(root, ec)) {
    error = "no such file or folder: " + path;
    return false;
  }
  // A DICOMDIR: read its image records; any other file is scanned on its own.
  DcmFileFormat probe;
  bool isDicomDir = false;
  if (probe.loadFileUntilTag(path.c_str(), EXS_Unknown, EGL_noChange, DCM_MaxReadLength, ERM_autoDetect, DCM_PixelData)
          .good()) {
    isDicomDir = GetString(probe.getMetaInfo(), DCM_MediaStorageSOPClassUID) == UID_MediaStorageDirectoryStorage;
  }
  if (isDicomDir) return DicomDirFiles(path, files, error);
  files.push_back(path);
  return true;
}

// The items of a sequence, in order.
std::vector<DcmItem*> Items(DcmItem* parent, const DcmTagKey& sequence) {
  std::vector<DcmItem*> items;
  DcmItem* item = nullptr;
  for (long i = 0; parent && parent->findAndGetSequenceItem(sequence, item, i).good() && item; ++i) items.push_back(item);
  return items;
}

// A SEG or RTSTRUCT among the files without images: listed with the series it references.
// False for any other kind of file.
bool AddSegmentationObject(DcmFileFormat& format, const SliceHeader& h, DicomScanResult& result) {
  DcmDataset* ds = format.getDataset();
  const std::string sopClass = GetString(ds, DCM_SOPClassUID);
  const bool seg = sopClass == UID_SegmentationStorage;
  if (!seg && sopClass != UID_RTStructureSetStorage) return false;
  DicomSegmentationObjectInfo info;
  info.File = h.File;
  info.Kind = seg ? "SEG" : "RTSTRUCT";
  info.SeriesInstanceUID = h.SeriesUID;
  info.StudyInstanceUID = h.StudyUID;
  info.FrameOfReferenceUID = h.FrameOfReferenceUID;
  info.SeriesDescription = h.Description;
  info.SeriesNumber = h.SeriesNumber;
  info.TransferSyntaxUID = h.TransferSyntax;
  if (seg) {
    for (DcmItem* series : Items(ds, DCM_ReferencedSeriesSequence))
      if (info.ReferencedSeriesUID.empty()) info.ReferencedSeriesUID = GetString(series, DCM_SeriesInstanceUID);
    for (DcmItem* segment : Items(ds, DCM_SegmentSequence)) info.Segments.push_back(GetString(segment, DCM_SegmentLabel));
  } else {
    // Referenced Frame of Reference > RT Referenced Study > RT Referenced Series.
    for (DcmItem* frame : Items(ds, DCM_ReferencedFrameOfReferenceSequence)) {
      if (info.FrameOfReferenceUID.empty()) info.FrameOfReferenceUID = GetString(frame, DCM_FrameOfReferenceUID);
      for (DcmItem* study : Items(frame, DCM_RTReferencedStudySequence))
        for (DcmItem* series : Items(study, DCM_RTReferencedSeriesSequence))
          if (info.ReferencedSeriesUID.empty()) info.ReferencedSeriesUID = GetString(series, DCM_SeriesInstanceUID);
    }
    for (DcmItem* roi : Items(ds, DCM_StructureSetROISequence)) info.Segments.push_back(GetString(roi, DCM_ROIName));
    if (info.SeriesDescription.empty()) info.SeriesDescription = GetString(ds, DCM_StructureSetLabel);
  }
  result.Segmentations.push_back(std::move(info));
  return true;
}

// One listed stack of a series from its images' headers.
DicomSeriesInfo StackInfo(const std::string& uid, const std::vector<SliceHeader>& headers, size_t index, size_t count,
                          const std::vector<std::string>& corruptFiles) {
  DicomSeriesInfo info;
  const SliceHeader& h = headers.front();
  info.SeriesInstanceUID = uid;
  info.StackIndex = static_cast<int>(index) + 1;
  info.StackCount = static_cast<int>(count);
  info.StackID = count == 1 ? uid : uid + "#" + std::to_string(index + 1);
  info.StudyInstanceUID = h.StudyUID;
  info.FrameOfReferenceUID = h.FrameOfReferenceUID;
  info.Modality = h.Modality;
  info.SeriesDescription = h.Description;
  info.PatientName = h.PatientName;
  info.SeriesNumber = h.SeriesNumber;
  info.TransferSyntaxUID = h.TransferSyntax;
  info.Files = DistinctFiles(headers);
  info.Slices = static_cast<int>(headers.size());
  info.Columns = h.Columns;
  info.Rows = h.Rows;
  info.PixelSpacing[0] = h.PixelSpacing[0];
  info.PixelSpacing[1] = h.PixelSpacing[1];
  std::copy(h.Orientation, h.Orientation + 6, info.Orientation);
  info.OrientationName = h.HasOrientation ? OrientationName(h.Orientation) : "no orientation";
  const SeriesGeometry g = AnalyzeGeometry(headers, DicomReadOptions().SpacingTolerance);
  info.SliceSpacing = g.Problem.empty() ? g.Spacing : 0.0;
  info.Problem = !g.Problem.empty() ? g.Problem : g.IrregularMessage;
  info.Warnings = SeriesNotes(headers);
  if (!h.HasPixelSpacing && info.Warnings.empty())
    info.Warnings.push_back("no PixelSpacing in " + Name(h.File) + ": 1 mm pixels assumed");
  info.CorruptFiles = corruptFiles;
  if (!info.CorruptFiles.empty()) info.Problem = "corrupt or truncated file " + info.CorruptFiles.front();
  return info;
}

// Series Number as a number for ordering (a series without one after those with one).
long SeriesNumberKey(const std::string& number) {
  try {
    return number.empty() ? LONG_MAX : std::stol(number);
  } catch (...) {
    return LONG_MAX;
  }
}

// Whatever the order of the files: image series and segmentation objects by Series Number, then
// UID (a series' stacks keep their order), as a PACS lists a study.
void SortBySeries(DicomScanResult& result) {
  std::stable_sort(result.Series.begin(), result.Series.end(), [](const DicomSeriesInfo& a, const DicomSeriesInfo& b) {
    const long x = SeriesNumberKey(a.SeriesNumber), y = SeriesNumberKey(b.SeriesNumber);
    return x != y ? x < y : a.SeriesInstanceUID < b.SeriesInstanceUID;
  });
  std::stable_sort(result.Segmentations.begin(), result.Segmentations.end(),
                   [](const DicomSegmentationObjectInfo& a, const DicomSegmentationObjectInfo& b) {
                     const long x = SeriesNumberKey(a.SeriesNumber), y = SeriesNumberKey(b.SeriesNumber);
                     if (x != y) return x < y;
                     return a.SeriesInstanceUID != b.SeriesInstanceUID ? a.SeriesInstanceUID < b.SeriesInstanceUID
                                                                       : a.File < b.File;
                   });
}

}  // namespace

bool ScanDicom(const std::string& path, DicomScanResult& result, std::string& error, const ProgressCallback& progress) {
  InitializeDcmtk();
  result = DicomScanResult();
  std::vector<std::string> files;
  if (!ListFiles(path, files, error)) return false;
  std::map<std::string, std::vector<SliceHeader>> bySeries;
  std::map<std::string, std::vector<std::string>> corruptBySeries;
  std::vector<std::string> seriesOrder;
  for (size_t f = 0; f < files.size(); ++f) {
    ++result.FilesExamined;
    DcmFileFormat format;
    SliceHeader h;
    std::string reason;
    switch (LoadFile(files[f], format, h, reason, true)) {
      case FileKind::NotDicom: ++result.NonDicomFiles; break;
      case FileKind::NonImage:
        if (!AddSegmentationObject(format, h, result)) ++result.NonImageDicomFiles;
        break;
      case FileKind::Corrupt:
        result.CorruptFiles.push_back(files[f] + ": " + reason);
        if (!h.SeriesUID.empty()) corruptBySeries[h.SeriesUID].push_back(files[f] + ": " + reason);
        break;
      case FileKind::Image:
        if (h.SeriesUID.empty()) h.SeriesUID = "(no SeriesInstanceUID)";
        if (!bySeries.count(h.SeriesUID)) seriesOrder.push_back(h.SeriesUID);
        ExpandFrames(format, h, bySeries[h.SeriesUID]);
        break;
    }
    if (progress && (f % 16 == 0 || f + 1 == files.size())) progress(double(f + 1) / files.size(), "scanning");
  }
  for (const std::string& uid : seriesOrder) {
    const std::vector<std::vector<SliceHeader>> stacks = SplitIntoStacks(std::move(bySeries[uid]));
    for (size_t s = 0; s < stacks.size(); ++s)
      result.Series.push_back(StackInfo(uid, stacks[s], s, stacks.size(), corruptBySeries[uid]));
  }
  SortBySeries(result);
  return true;
}

}  // namespace rp
