#include "rpDicomSeries.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>
#include <type_traits>

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcdicdir.h>
#include <dcmtk/dcmdata/dcrledrg.h>
#include <dcmtk/dcmdata/dctk.h>
#include <dcmtk/dcmjpeg/djdecode.h>
#include <dcmtk/oflog/oflog.h>

#include <vtkDataArray.h>
#include <vtkPointData.h>

#include "rpDicomCommon.h"
#include "rpDicomGdcmDecoder.h"
#include "rpDicomJpegLsDecoder.h"
#include "rpDicomTransferSyntax.h"
#include "rpLPSRAS.h"
#include "rpMemoryBudget.h"

namespace fs = std::filesystem;

namespace rp {

void InitializeDcmtk() {
  static std::once_flag once;
  std::call_once(once, []() {
    DJDecoderRegistration::registerCodecs();
    DcmRLEDecoderRegistration::registerCodecs();
    // Elements written as UN (e.g. by gdcmconv from an implicit-VR file: RescaleIntercept,
    // PixelSpacing...) are read with their dictionary VR, or their values would be lost.
    dcmEnableUnknownVRConversion.set(OFTrue);
    // DCMTK logs parser warnings on stderr; our messages say what went wrong instead.
    // ROBOPLAN_DCMTK_LOG=1 shows DCMTK's own warnings and errors (e.g. which attribute of a SEG
    // it finds missing).
    const char* log = std::getenv("ROBOPLAN_DCMTK_LOG");
    OFLog::configure(log && *log && std::string(log) != "0" ? OFLogger::WARN_LOG_LEVEL : OFLogger::FATAL_LOG_LEVEL);
    // Unregistered at exit, so the codec list is not reported as a leak.
    std::atexit([]() {
      DcmRLEDecoderRegistration::cleanup();
      DJDecoderRegistration::cleanup();
    });
  });
}

std::string OrientationName(const double iop[6]) {
  const double n[3] = {iop[1] * iop[5] - iop[2] * iop[4], iop[2] * iop[3] - iop[0] * iop[5],
                       iop[0] * iop[4] - iop[1] * iop[3]};
  const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (length < 1e-6) return "degenerate";
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(n[a]) > std::abs(n[axis])) axis = a;
  const char* names[3] = {"sagittal", "coronal", "axial"};  // normal along x (L), y (P), z (S)
  const double degrees = std::acos(std::min(1.0, std::abs(n[axis]) / length)) * 180.0 / M_PI;
  if (degrees < 0.5) return names[axis];
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(1);
  s << "oblique " << names[axis] << " (" << degrees << "°)";
  return s.str();
}

namespace {

enum class FileKind { Image, NonImage, NotDicom, Corrupt };

// One image: a single-frame file, or one frame of a multi-frame file.
struct SliceHeader {
  std::string File;
  int Frame = 0;  // index of the frame in its file
  std::string SeriesUID, StudyUID, Modality, Description, PatientName, SeriesNumber, TransferSyntax;
  std::string Photometric;
  int Rows = 0, Columns = 0, Frames = 1, Samples = 1;
  int BitsAllocated = 16, BitsStored = 16, PixelRepresentation = 0;
  bool HasPosition = false, HasOrientation = false, HasPixelSpacing = false, HasWindow = false;
  bool MultiFrameWithoutPositions = false;
  double Position[3] = {0, 0, 0};
  double Orientation[6] = {1, 0, 0, 0, 1, 0};
  double PixelSpacing[2] = {1, 1};
  double Slope = 1.0, Intercept = 0.0;
  double WindowCenter = 0.0, WindowWidth = 0.0;
  double SliceThickness = 0.0, SpacingBetweenSlices = 0.0;
  // Modality LUT Sequence (0028,3000): stored value v -> LutData[clamp(v - LutFirst)].
  std::vector<int32_t> LutData;
  int LutFirst = 0;
  // Non-fatal notes on this image (bad PixelSpacing, assumed slice spacing...): warnings.
  std::vector<std::string> Notes;
  // Why this image cannot be read, found in its header ("" if none): refused.
  std::string HeaderProblem;
};

bool HasPart10Preamble(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char buffer[132];
  if (!in.read(buffer, 132)) return false;
  return std::memcmp(buffer + 128, "DICM", 4) == 0;
}

std::string GetString(DcmItem* item, const DcmTagKey& tag) {
  OFString value;
  if (item->findAndGetOFStringArray(tag, value).good()) {
    std::string s = value.c_str();
    while (!s.empty() && (s.back() == ' ' || s.back() == '\0')) s.pop_back();
    return s;
  }
  return "";
}

bool GetDoubles(DcmItem* item, const DcmTagKey& tag, double* values, int count) {
  for (int i = 0; i < count; ++i) {
    Float64 v = 0;
    if (item->findAndGetFloat64(tag, v, static_cast<unsigned long>(i)).bad()) return false;
    values[i] = v;
  }
  return true;
}

int GetInt(DcmItem* item, const DcmTagKey& tag, int fallback) {
  Uint16 u = 0;
  if (item->findAndGetUint16(tag, u).good()) return u;
  Sint32 s = 0;
  if (item->findAndGetSint32(tag, s).good()) return s;
  const std::string text = GetString(item, tag);
  if (!text.empty()) {
    try {
      return std::stoi(text);
    } catch (...) {
    }
  }
  return fallback;
}

// PixelSpacing must be two finite positive numbers; anything else (0\0, negative, NaN) is
// treated as missing: 1 mm pixels, with a note naming the value found.
void CheckPixelSpacing(DcmItem* item, SliceHeader& h) {
  if (!item->tagExists(DCM_PixelSpacing)) return;
  const double* p = h.PixelSpacing;
  if (h.HasPixelSpacing && std::isfinite(p[0]) && std::isfinite(p[1]) && p[0] > 0.0 && p[1] > 0.0) return;
  h.Notes.push_back("PixelSpacing " + GetString(item, DCM_PixelSpacing) + " in " +
                    fs::path(h.File).filename().string() + " is not a valid spacing: 1 mm pixels assumed");
  h.HasPixelSpacing = false;
  h.PixelSpacing[0] = h.PixelSpacing[1] = 1.0;
}

// The Modality LUT Sequence (0028,3000), PS3.3 C.11.1: LUT Descriptor = entries (0 means
// 65536), first stored value mapped (signed when the pixels are), bits per entry (8 or 16);
// LUT Data = the output values. It replaces RescaleSlope/Intercept.
void ReadModalityLut(DcmItem* ds, SliceHeader& h) {
  DcmItem* lut = nullptr;
  if (ds->findAndGetSequenceItem(DCM_ModalityLUTSequence, lut, 0).bad() || !lut) return;
  const std::string where = "Modality LUT Sequence (0028,3000) of " + fs::path(h.File).filename().string();
  Uint16 descriptor[3] = {0, 0, 0};
  for (unsigned long i = 0; i < 3; ++i) {
    Sint16 s = 0;
    if (lut->findAndGetUint16(DCM_LUTDescriptor, descriptor[i], i).bad()) {
      if (lut->findAndGetSint16(DCM_LUTDescriptor, s, i).bad()) {
        h.HeaderProblem = where + ": no valid LUT Descriptor (0028,3002)";
        return;
      }
      descriptor[i] = static_cast<Uint16>(s);
    }
  }
  const size_t entries = descriptor[0] == 0 ? 65536 : descriptor[0];
  const int bits = descriptor[2];
  h.LutFirst = h.PixelRepresentation == 1 ? static_cast<int>(static_cast<int16_t>(descriptor[1])) : descriptor[1];
  DcmElement* data = nullptr;
  Uint16* words = nullptr;
  if (lut->findAndGetElement(DCM_LUTData, data).bad() || !data || data->getUint16Array(words).bad() || !words) {
    h.HeaderProblem = where + ": no LUT Data (0028,3006)";
    return;
  }
  const size_t count = data->getLength() / 2;
  if (bits < 1 || bits > 16) {
    h.HeaderProblem = where + ": " + std::to_string(bits) + " bits per LUT entry (8 or 16 expected)";
    return;
  }
  h.LutData.resize(entries);
  if (bits <= 8 && count < entries && 2 * count >= entries) {  // 8-bit entries packed two per word
    for (size_t i = 0; i < entries; ++i) h.LutData[i] = (words[i / 2] >> (8 * (i % 2))) & 0xff;
  } else if (count >= entries) {
    for (size_t i = 0; i < entries; ++i) h.LutData[i] = words[i] & ((1u << bits) - 1u);
  } else {
    h.HeaderProblem = where + ": " + std::to_string(count) + " LUT Data values for " + std::to_string(entries) +
                      " entries in its descriptor";
    h.LutData.clear();
    return;
  }
  if (ds->tagExists(DCM_RescaleSlope) || ds->tagExists(DCM_RescaleIntercept))
    h.Notes.push_back(where + " applied; RescaleSlope/Intercept beside it ignored (the standard allows only one)");
  h.Slope = 1.0;
  h.Intercept = 0.0;
}

// The first item of a functional group macro (e.g. PlanePositionSequence) for one frame: from
// the frame's item of the per-frame sequence, else from the shared one.
DcmItem* FunctionalGroup(DcmItem* perFrame, DcmItem* shared, const DcmTagKey& macro) {
  DcmItem* item = nullptr;
  if (perFrame && perFrame->findAndGetSequenceItem(macro, item, 0).good() && item) return item;
  if (shared && shared->findAndGetSequenceItem(macro, item, 0).good() && item) return item;
  return nullptr;
}

// Geometry, rescale and window of frame `frame` from the Enhanced (multi-frame) functional
// groups; values found there override the top-level ones.
void ReadFunctionalGroups(DcmItem* ds, int frame, SliceHeader& h, bool& hasFramePosition) {
  DcmItem* shared = nullptr;
  DcmItem* perFrame = nullptr;
  ds->findAndGetSequenceItem(DCM_SharedFunctionalGroupsSequence, shared, 0);
  ds->findAndGetSequenceItem(DCM_PerFrameFunctionalGroupsSequence, perFrame, frame);
  hasFramePosition = false;
  if (DcmItem* g = FunctionalGroup(perFrame, shared, DCM_PlanePositionSequence)) {
    hasFramePosition = GetDoubles(g, DCM_ImagePositionPatient, h.Position, 3);
    h.HasPosition = h.HasPosition || hasFramePosition;
  }
  if (DcmItem* g = FunctionalGroup(perFrame, shared, DCM_PlaneOrientationSequence))
    h.HasOrientation = GetDoubles(g, DCM_ImageOrientationPatient, h.Orientation, 6) || h.HasOrientation;
  if (DcmItem* g = FunctionalGroup(perFrame, shared, DCM_PixelMeasuresSequence)) {
    if (g->tagExists(DCM_PixelSpacing)) {
      h.HasPixelSpacing = GetDoubles(g, DCM_PixelSpacing, h.PixelSpacing, 2);
      CheckPixelSpacing(g, h);
    }
    GetDoubles(g, DCM_SliceThickness, &h.SliceThickness, 1);
    GetDoubles(g, DCM_SpacingBetweenSlices, &h.SpacingBetweenSlices, 1);
  }
  if (DcmItem* g = FunctionalGroup(perFrame, shared, DCM_PixelValueTransformationSequence)) {
    if (!GetDoubles(g, DCM_RescaleSlope, &h.Slope, 1) || h.Slope == 0.0) h.Slope = 1.0;
    if (!GetDoubles(g, DCM_RescaleIntercept, &h.Intercept, 1)) h.Intercept = 0.0;
  }
  if (DcmItem* g = FunctionalGroup(perFrame, shared, DCM_FrameVOILUTSequence)) {
    h.HasWindow = GetDoubles(g, DCM_WindowCenter, &h.WindowCenter, 1) &&
                  GetDoubles(g, DCM_WindowWidth, &h.WindowWidth, 1) && h.WindowWidth > 0.0;
  }
}


void ReadHeader(DcmFileFormat& format, SliceHeader& h) {
  DcmDataset* ds = format.getDataset();
  h.SeriesUID = GetString(ds, DCM_SeriesInstanceUID);
  h.StudyUID = GetString(ds, DCM_StudyInstanceUID);
  h.Modality = GetString(ds, DCM_Modality);
  h.Description = GetString(ds, DCM_SeriesDescription);
  h.PatientName = GetString(ds, DCM_PatientName);
  h.SeriesNumber = GetString(ds, DCM_SeriesNumber);
  h.Photometric = GetString(ds, DCM_PhotometricInterpretation);
  h.TransferSyntax = GetString(format.getMetaInfo(), DCM_TransferSyntaxUID);
  if (h.TransferSyntax.empty()) h.TransferSyntax = DcmXfer(ds->getOriginalXfer()).getXferID();
  h.Rows = GetInt(ds, DCM_Rows, 0);
  h.Columns = GetInt(ds, DCM_Columns, 0);
  h.Frames = std::max(1, GetInt(ds, DCM_NumberOfFrames, 1));
  h.Samples = GetInt(ds, DCM_SamplesPerPixel, 1);
  h.BitsAllocated = GetInt(ds, DCM_BitsAllocated, 16);
  h.BitsStored = GetInt(ds, DCM_BitsStored, h.BitsAllocated);
  h.PixelRepresentation = GetInt(ds, DCM_PixelRepresentation, 0);
  h.HasPosition = GetDoubles(ds, DCM_ImagePositionPatient, h.Position, 3);
  h.HasOrientation = GetDoubles(ds, DCM_ImageOrientationPatient, h.Orientation, 6);
  h.HasPixelSpacing = GetDoubles(ds, DCM_PixelSpacing, h.PixelSpacing, 2);
  if (!GetDoubles(ds, DCM_RescaleSlope, &h.Slope, 1) || h.Slope == 0.0) h.Slope = 1.0;
  if (!GetDoubles(ds, DCM_RescaleIntercept, &h.Intercept, 1)) h.Intercept = 0.0;
  h.HasWindow = GetDoubles(ds, DCM_WindowCenter, &h.WindowCenter, 1) &&
                GetDoubles(ds, DCM_WindowWidth, &h.WindowWidth, 1) && h.WindowWidth > 0.0;
  GetDoubles(ds, DCM_SliceThickness, &h.SliceThickness, 1);
  GetDoubles(ds, DCM_SpacingBetweenSlices, &h.SpacingBetweenSlices, 1);
  // RT Dose scales its stored values with DoseGridScaling (Gy per unit), not a rescale.
  double doseScaling = 0.0;
  if (h.Modality == "RTDOSE" && !ds->tagExists(DCM_RescaleSlope) && GetDoubles(ds, DCM_DoseGridScaling, &doseScaling, 1) &&
      doseScaling > 0.0 && std::isfinite(doseScaling))
    h.Slope = doseScaling;
  CheckPixelSpacing(ds, h);
  ReadModalityLut(ds, h);
  if (h.Photometric == "PALETTE COLOR")
    h.HeaderProblem = "PALETTE COLOR image (" + fs::path(h.File).filename().string() +
                      "): its pixels are indices into a colour palette, not intensities, and colour is not read "
                      "(convert it to greyscale, MONOCHROME2, first)";
  else if (h.Samples != 1 || (!h.Photometric.empty() && h.Photometric != "MONOCHROME1" && h.Photometric != "MONOCHROME2"))
    h.HeaderProblem = "colour image (" + (h.Photometric.empty() ? std::string("no PhotometricInterpretation") : h.Photometric) +
                      ", " + std::to_string(h.Samples) + " sample(s) per pixel, " + fs::path(h.File).filename().string() +
                      ") is not read: RoboPlan's volumes are scalar (convert it to greyscale, MONOCHROME2, first; "
                      "see Libs/Imaging/README.md)";
}


// "" when the whole file parses and its native pixel data holds every frame; else why not.
// (Read in full: only for a file about to be refused for another reason.)
std::string TruncatedReason(const SliceHeader& h) {
  DcmFileFormat format;
  const std::string name = fs::path(h.File).filename().string();
  const OFCondition status = format.loadFile(h.File.c_str());
  if (status.bad()) return "corrupt or truncated file " + name + " (" + status.text() + ")";
  DcmDataset* ds = format.getDataset();
  DcmElement* pixels = nullptr;
  if (DcmXfer(ds->getOriginalXfer()).isEncapsulated() || ds->findAndGetElement(DCM_PixelData, pixels).bad() || !pixels)
    return "";
  const size_t needed = static_cast<size_t>(h.Rows) * h.Columns * h.Frames * std::max(1, h.Samples) *
                        std::max(1, h.BitsAllocated) / 8;
  if (pixels->getLength() >= needed) return "";
  return "truncated file " + name + ": pixel data of " + std::to_string(pixels->getLength()) + " bytes for " +
         std::to_string(h.Frames) + " frame(s) of " + std::to_string(needed) + " bytes";
}

// Frames of a multi-frame file without functional groups, placed the standard ways: RT Dose by
// its Grid Frame Offset Vector (3004,000C), PS3.3 C.8.8.3.2 (relative: first offset 0; absolute:
// first offset = the position along the normal; either way frame f lies (offset[f] - offset[0])
// along the normal from ImagePositionPatient); legacy multi-frame MR/NM/CT by the top-level (or
// NM Detector Information) position and orientation plus Spacing Between Slices (or, failing
// that, Slice Thickness, with a warning). Without these the frames are refused.
void ExpandLegacyFrames(DcmItem* ds, const SliceHeader& file, std::vector<SliceHeader>& out) {
  SliceHeader base = file;
  DcmItem* detector = nullptr;
  if ((!base.HasPosition || !base.HasOrientation) &&
      ds->findAndGetSequenceItem(DCM_DetectorInformationSequence, detector, 0).good() && detector) {
    base.HasPosition = GetDoubles(detector, DCM_ImagePositionPatient, base.Position, 3);
    base.HasOrientation = GetDoubles(detector, DCM_ImageOrientationPatient, base.Orientation, 6);
  }
  const std::string name = fs::path(file.File).filename().string();
  const std::string frames = std::to_string(file.Frames) + " frames in " + name;
  auto refuse = [&](const std::string& why) {
    out.push_back(base);
    out.back().MultiFrameWithoutPositions = true;
    // A truncated file is reported as truncated, whatever else it lacks.
    const std::string truncated = TruncatedReason(file);
    out.back().HeaderProblem = !truncated.empty() ? truncated
                                                  : "multi-frame image without the geometry of its frames (" + frames +
                                                        ": " + why + ")";
  };
  if (!base.HasPosition || !base.HasOrientation)
    return refuse("no ImagePositionPatient and ImageOrientationPatient");
  std::vector<double> offsets(file.Frames, 0.0);
  const bool grid = ds->tagExists(DCM_GridFrameOffsetVector);
  if (grid) {
    if (!GetDoubles(ds, DCM_GridFrameOffsetVector, offsets.data(), file.Frames))
      return refuse("GridFrameOffsetVector has fewer than " + std::to_string(file.Frames) + " values");
    const double first = offsets.front();
    for (double& o : offsets) o -= first;
  } else {
    const int slices = GetInt(ds, DCM_NumberOfSlices, file.Frames);
    if (slices != file.Frames)
      return refuse("NumberOfSlices " + std::to_string(slices) + ": the frames are not one slice each");
    double step = file.SpacingBetweenSlices;
    if (step == 0.0 && file.SliceThickness > 0.0) {
      step = file.SliceThickness;
      base.Notes.push_back("multi-frame " + name + " has no SpacingBetweenSlices: frames assumed " +
                           std::to_string(step) + " mm apart (its SliceThickness)");
    }
    if (step == 0.0 || !std::isfinite(step)) return refuse("no SpacingBetweenSlices, SliceThickness or GridFrameOffsetVector");
    for (int f = 0; f < file.Frames; ++f) offsets[f] = f * step;
  }
  double normal[3] = {base.Orientation[1] * base.Orientation[5] - base.Orientation[2] * base.Orientation[4],
                      base.Orientation[2] * base.Orientation[3] - base.Orientation[0] * base.Orientation[5],
                      base.Orientation[0] * base.Orientation[4] - base.Orientation[1] * base.Orientation[3]};
  const double length = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
  if (length < 1e-6) return refuse("degenerate ImageOrientationPatient");
  for (int f = 0; f < file.Frames; ++f) {
    SliceHeader h = base;
    h.Frame = f;
    for (int a = 0; a < 3; ++a) h.Position[a] = base.Position[a] + offsets[f] * normal[a] / length;
    out.push_back(std::move(h));
  }
}

// One header per image of the file: itself, or one per frame of a multi-frame file (with the
// frame's functional groups applied).
void ExpandFrames(DcmFileFormat& format, const SliceHeader& file, std::vector<SliceHeader>& out) {
  DcmDataset* ds = format.getDataset();
  const bool enhanced = ds->tagExists(DCM_PerFrameFunctionalGroupsSequence) ||
                        ds->tagExists(DCM_SharedFunctionalGroupsSequence);
  if (!enhanced) {
    if (file.Frames == 1)
      out.push_back(file);
    else
      ExpandLegacyFrames(ds, file, out);
    return;
  }
  std::string truncated;
  bool checked = false;
  for (int f = 0; f < file.Frames; ++f) {
    SliceHeader h = file;
    h.Frame = f;
    bool hasFramePosition = false;
    ReadFunctionalGroups(ds, f, h, hasFramePosition);
    h.MultiFrameWithoutPositions = file.Frames > 1 && !hasFramePosition;
    if (h.MultiFrameWithoutPositions) {
      if (!checked) truncated = TruncatedReason(file);  // once per file
      checked = true;
      h.HeaderProblem = !truncated.empty() ? truncated
                                           : "multi-frame image without a position per frame (" +
                                                 std::to_string(file.Frames) + " frames in " +
                                                 fs::path(file.File).filename().string() +
                                                 ", no PerFrameFunctionalGroupsSequence with PlanePositionSequence)";
    }
    out.push_back(std::move(h));
  }
}

// Loads a file (only up to the pixel data when `headerOnly`) and classifies it.
FileKind LoadFile(const std::string& path, DcmFileFormat& format, SliceHeader& h, std::string& reason,
                  bool headerOnly) {
  const bool part10 = HasPart10Preamble(path);
  OFCondition status =
      headerOnly ? format.loadFileUntilTag(path.c_str(), EXS_Unknown, EGL_noChange, DCM_MaxReadLength,
                                           ERM_autoDetect, DCM_FloatPixelData)
                 : format.loadFile(path.c_str(), EXS_Unknown, EGL_noChange, DCM_MaxReadLength, ERM_autoDetect);
  DcmDataset* ds = format.getDataset();
  const bool looksDicom = part10 || ds->tagExists(DCM_SOPClassUID) || ds->tagExists(DCM_StudyInstanceUID) ||
                          ds->tagExists(DCM_SeriesInstanceUID);
  if (status.bad()) {
    if (!looksDicom) return FileKind::NotDicom;
    reason = std::string("corrupt or truncated DICOM (") + status.text() + ")";
    h.File = path;
    h.SeriesUID = GetString(ds, DCM_SeriesInstanceUID);  // may survive in a truncated file
    return FileKind::Corrupt;
  }
  if (!looksDicom) return FileKind::NotDicom;
  h.File = path;
  ReadHeader(format, h);
  // A segmentation (SEG) has frames but is read by rpDicomSegmentation, not as an image.
  if (h.Rows <= 0 || h.Columns <= 0 || GetString(ds, DCM_SOPClassUID) == UID_SegmentationStorage)
    return FileKind::NonImage;
  if (!headerOnly && !ds->tagExists(DCM_PixelData) && !ds->tagExists(DCM_FloatPixelData) &&
      !ds->tagExists(DCM_DoubleFloatPixelData)) {
    reason = "no pixel data (truncated file?)";
    return FileKind::Corrupt;
  }
  // Native (uncompressed, not deflated) pixel data: a file shorter than its frames is truncated,
  // whatever else is wrong with it.
  const DcmXfer xfer(ds->getOriginalXfer());
  if (headerOnly && !xfer.isEncapsulated() && xfer.getStreamCompression() == ESC_none) {
    const uintmax_t needed = static_cast<uintmax_t>(h.Rows) * h.Columns * h.Frames * std::max(1, h.Samples) *
                             std::max(1, h.BitsAllocated) / 8;
    std::error_code ec;
    const uintmax_t size = fs::file_size(path, ec);
    if (!ec && size < needed) {
      reason = "truncated file: " + std::to_string(size) + " bytes cannot hold " + std::to_string(h.Frames) +
               " frame(s) of " + std::to_string(h.Columns) + "x" + std::to_string(h.Rows) + " " +
               std::to_string(h.BitsAllocated) + "-bit pixels (" + std::to_string(needed) + " bytes)";
      return FileKind::Corrupt;
    }
  }
  return FileKind::Image;
}

void Cross(const double a[3], const double b[3], double c[3]) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}
double Dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

std::string Fmt(double v, int precision = 2) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(precision);
  s << v;
  return s.str();
}

std::string Name(const std::string& path) { return fs::path(path).filename().string(); }

// Images of one stack share orientation, image size and pixel spacing.
bool SameStack(const SliceHeader& a, const SliceHeader& b) {
  if (a.Rows != b.Rows || a.Columns != b.Columns || a.HasOrientation != b.HasOrientation) return false;
  for (int i = 0; i < 6; ++i)
    if (std::abs(a.Orientation[i] - b.Orientation[i]) > 1e-3) return false;
  return std::abs(a.PixelSpacing[0] - b.PixelSpacing[0]) <= 1e-4 &&
         std::abs(a.PixelSpacing[1] - b.PixelSpacing[1]) <= 1e-4;
}

// Splits the images of one series into stacks, in the order their first image was found.
std::vector<std::vector<SliceHeader>> SplitIntoStacks(std::vector<SliceHeader> headers) {
  std::vector<std::vector<SliceHeader>> stacks;
  for (SliceHeader& h : headers) {
    auto it = std::find_if(stacks.begin(), stacks.end(),
                           [&](const std::vector<SliceHeader>& s) { return SameStack(s.front(), h); });
    if (it == stacks.end()) {
      stacks.emplace_back();
      it = stacks.end() - 1;
    }
    it->push_back(std::move(h));
  }
  return stacks;
}

std::vector<std::string> DistinctFiles(const std::vector<SliceHeader>& headers) {
  std::vector<std::string> files;
  for (const SliceHeader& h : headers)
    if (files.empty() || files.back() != h.File) files.push_back(h.File);
  return files;
}

// Slice order and spacing of one stack from its headers.
struct SeriesGeometry {
  std::vector<size_t> Order;         // header indices sorted along the normal
  std::vector<double> Positions;     // sorted positions along the normal
  double Normal[3] = {0, 0, 1};
  double Spacing = 1.0;              // median gap
  double MinGap = 1.0;
  bool Irregular = false;            // missing slice / uneven spacing
  std::string IrregularMessage;
  std::string Problem;               // refused outright
};

SeriesGeometry AnalyzeGeometry(const std::vector<SliceHeader>& headers, double tolerance) {
  SeriesGeometry g;
  if (headers.empty()) {
    g.Problem = "no image files";
    return g;
  }
  const SliceHeader& first = headers.front();
  for (const SliceHeader& h : headers) {
    if (!h.HeaderProblem.empty()) {
      g.Problem = h.HeaderProblem;
      return g;
    }
    const TransferSyntaxInfo* syntax = FindTransferSyntax(h.TransferSyntax);
    if (!syntax) {
      g.Problem = "transfer syntax " + h.TransferSyntax + " of " + Name(h.File) +
                  " is not one the reader decodes (see the README's table of transfer syntaxes)";
      return g;
    }
    if (headers.size() > 1 && !h.HasPosition) {
      g.Problem = "ImagePositionPatient missing in " + Name(h.File) + ": slices cannot be ordered";
      return g;
    }
  }
  double row[3] = {first.Orientation[0], first.Orientation[1], first.Orientation[2]};
  double col[3] = {first.Orientation[3], first.Orientation[4], first.Orientation[5]};
  Cross(row, col, g.Normal);
  const double n = std::sqrt(Dot3(g.Normal, g.Normal));
  if (n < 1e-3) {
    g.Problem = "degenerate ImageOrientationPatient in " + Name(first.File);
    return g;
  }
  for (double& v : g.Normal) v /= n;

  g.Order.resize(headers.size());
  for (size_t i = 0; i < headers.size(); ++i) g.Order[i] = i;
  std::vector<double> along(headers.size());
  for (size_t i = 0; i < headers.size(); ++i) along[i] = Dot3(headers[i].Position, g.Normal);
  std::stable_sort(g.Order.begin(), g.Order.end(), [&](size_t a, size_t b) { return along[a] < along[b]; });
  for (size_t i : g.Order) g.Positions.push_back(along[i]);

  auto where = [&](size_t index) {
    const SliceHeader& h = headers[index];
    return h.Frames > 1 ? Name(h.File) + " frame " + std::to_string(h.Frame + 1) : Name(h.File);
  };
  if (headers.size() == 1) {
    g.Spacing = first.SpacingBetweenSlices > 0 ? first.SpacingBetweenSlices
                                               : (first.SliceThickness > 0 ? first.SliceThickness : 1.0);
    g.MinGap = g.Spacing;
    return g;
  }
  std::vector<double> gaps;
  for (size_t k = 1; k < g.Positions.size(); ++k) {
    const double gap = g.Positions[k] - g.Positions[k - 1];
    if (gap < 1e-4) {
      g.Problem = "two slices at the same position " + Fmt(g.Positions[k], 3) + " mm (" + where(g.Order[k - 1]) +
                  ", " + where(g.Order[k]) +
                  "): several acquisitions, echoes or time points in one series are not supported";
      return g;
    }
    gaps.push_back(gap);
  }
  // Gantry tilt: positions must move along the normal only.
  const SliceHeader& h0 = headers[g.Order.front()];
  const SliceHeader& hn = headers[g.Order.back()];
  double d[3] = {hn.Position[0] - h0.Position[0], hn.Position[1] - h0.Position[1], hn.Position[2] - h0.Position[2]};
  const double axial = Dot3(d, g.Normal);
  double lateral[3] = {d[0] - axial * g.Normal[0], d[1] - axial * g.Normal[1], d[2] - axial * g.Normal[2]};
  const double lateralLength = std::sqrt(Dot3(lateral, lateral));
  if (lateralLength > 0.01 + 1e-3 * std::abs(axial)) {
    const double degrees = std::atan2(lateralLength, std::abs(axial)) * 180.0 / M_PI;
    g.Problem = "gantry tilt of " + Fmt(degrees, 1) +
                " degrees (slice positions do not follow the slice normal) is not supported";
    return g;
  }
  std::vector<double> sorted = gaps;
  std::sort(sorted.begin(), sorted.end());
  g.Spacing = sorted[sorted.size() / 2];
  g.MinGap = sorted.front();
  for (size_t k = 0; k < gaps.size(); ++k) {
    if (std::abs(gaps[k] - g.Spacing) > std::max(1e-3, tolerance * g.Spacing)) {
      const long multiple = std::lround(gaps[k] / g.Spacing);
      const bool missing = multiple >= 2 && std::abs(gaps[k] - multiple * g.Spacing) < std::max(1e-3, tolerance * g.Spacing);
      std::string between = "between positions " + Fmt(g.Positions[k]) + " mm (" + where(g.Order[k]) + ") and " +
                            Fmt(g.Positions[k + 1]) + " mm (" + where(g.Order[k + 1]) + "): gap " + Fmt(gaps[k]) +
                            " mm, expected " + Fmt(g.Spacing) + " mm";
      g.Irregular = true;
      g.IrregularMessage = missing ? std::to_string(multiple - 1) + " missing slice(s) " + between
                                   : "uneven slice spacing " + between;
      break;
    }
  }
  return g;
}

// Stored pixels → modality values (slope/intercept applied) into `out`, in tight loops.
// Integral series (integer slope and intercept) decode into int32, others into float.
template <typename Raw, typename Out>
void ConvertPixels(const Raw* in, size_t count, int bitsStored, bool isSigned, double slope, double intercept,
                   Out* out) {
  const bool masked = bitsStored < static_cast<int>(8 * sizeof(Raw));
  using U = std::make_unsigned_t<Raw>;
  const uint32_t mask = masked ? ((1u << bitsStored) - 1u) : 0xffffffffu;
  const uint32_t signBit = masked ? (1u << (bitsStored - 1)) : 0u;
  const bool identity = slope == 1.0 && intercept == 0.0;
  for (size_t i = 0; i < count; ++i) {
    int64_t v;
    if (masked) {
      const uint32_t u = static_cast<uint32_t>(static_cast<U>(in[i])) & mask;
      v = (isSigned && (u & signBit)) ? static_cast<int64_t>(u) - (int64_t(1) << bitsStored) : static_cast<int64_t>(u);
    } else {
      v = static_cast<int64_t>(in[i]);
    }
    if constexpr (std::is_integral_v<Out>) {
      out[i] = static_cast<Out>(identity ? v : v * static_cast<int64_t>(slope) + static_cast<int64_t>(intercept));
    } else {
      out[i] = static_cast<Out>(identity ? double(v) : double(v) * slope + intercept);
    }
  }
}

// Decoded pixel data of one file: all its frames, stored values, this machine's byte order.
struct DecodedPixels {
  const void* Data = nullptr;
  size_t Bytes = 0;
  int FloatBits = 0;  // 32 or 64: Float / Double Float Pixel Data (7FE0,0008 / 0009)
  std::vector<char> Owned;  // GDCM's output (DCMTK's stays inside its dataset)
};

// Stored values → Modality LUT output values, in place.
template <typename Out>
void ApplyModalityLut(const SliceHeader& h, Out* values, size_t count) {
  const int64_t last = static_cast<int64_t>(h.LutData.size()) - 1;
  for (size_t i = 0; i < count; ++i) {
    const int64_t index = std::clamp(static_cast<int64_t>(values[i]) - h.LutFirst, int64_t(0), last);
    values[i] = static_cast<Out>(h.LutData[static_cast<size_t>(index)]);
  }
}

// One frame of integer pixel data → modality values.
template <typename Out>
void ConvertIntegerFrame(const char* base, size_t count, const SliceHeader& h, Out* out) {
  const bool isSigned = h.PixelRepresentation == 1;
  const int bitsStored = std::clamp(h.BitsStored, 1, h.BitsAllocated);
  if (h.BitsAllocated == 16) {
    if (isSigned)
      ConvertPixels(reinterpret_cast<const int16_t*>(base), count, bitsStored, true, h.Slope, h.Intercept, out);
    else
      ConvertPixels(reinterpret_cast<const uint16_t*>(base), count, bitsStored, false, h.Slope, h.Intercept, out);
  } else if (h.BitsAllocated == 8) {
    if (isSigned)
      ConvertPixels(reinterpret_cast<const int8_t*>(base), count, bitsStored, true, h.Slope, h.Intercept, out);
    else
      ConvertPixels(reinterpret_cast<const uint8_t*>(base), count, bitsStored, false, h.Slope, h.Intercept, out);
  } else {
    if (isSigned)
      ConvertPixels(reinterpret_cast<const int32_t*>(base), count, 32, true, h.Slope, h.Intercept, out);
    else
      ConvertPixels(reinterpret_cast<const uint32_t*>(base), count, 32, false, h.Slope, h.Intercept, out);
  }
  if (!h.LutData.empty()) ApplyModalityLut(h, out, count);
}

// One frame of decoded pixel data → modality values.
template <typename Out>
bool ConvertFrame(const DecodedPixels& pixels, const SliceHeader& h, Out* out, std::string& error) {
  const size_t count = static_cast<size_t>(h.Rows) * h.Columns;
  const int bits = pixels.FloatBits ? pixels.FloatBits : h.BitsAllocated;
  const size_t bytesPerPixel = static_cast<size_t>(bits / 8);
  const size_t offset = static_cast<size_t>(h.Frame) * count * bytesPerPixel;
  if (!pixels.FloatBits && h.BitsAllocated != 8 && h.BitsAllocated != 16 && h.BitsAllocated != 32) {
    error = std::to_string(h.BitsAllocated) + " bits allocated is not supported";
    return false;
  }
  if (!pixels.Data || pixels.Bytes < offset + count * bytesPerPixel) {
    error = "pixel data shorter than " + std::to_string(h.Frame + 1) + " frame(s) of " + std::to_string(h.Columns) +
            "x" + std::to_string(h.Rows) + " " + std::to_string(bits) + "-bit pixels (truncated file)";
    return false;
  }
  const char* base = static_cast<const char*>(pixels.Data) + offset;
  if (pixels.FloatBits == 32) {
    const float* in = reinterpret_cast<const float*>(base);
    std::transform(in, in + count, out, [](float v) { return static_cast<Out>(v); });
  } else if (pixels.FloatBits == 64) {
    const double* in = reinterpret_cast<const double*>(base);
    std::transform(in, in + count, out, [](double v) { return static_cast<Out>(v); });
  } else {
    ConvertIntegerFrame(base, count, h, out);
  }
  return true;
}

// Decodes the pixel data of one file with the library its transfer syntax needs. `format`
// must outlive `pixels` (DCMTK's buffer stays inside it).
bool DecodeFile(const SliceHeader& h, DcmFileFormat& format, DecodedPixels& pixels, std::string& error) {
  const TransferSyntaxInfo* syntax = FindTransferSyntax(h.TransferSyntax);
  if (syntax && syntax->Decoder == PixelDecoder::GDCM) {
    if (!DecodePixelsWithGdcm(h.File, pixels.Owned, error)) {
      error = TransferSyntaxLabel(h.TransferSyntax) + ": " + error;
      return false;
    }
    pixels.Data = pixels.Owned.data();
    pixels.Bytes = pixels.Owned.size();
    return true;
  }
  SliceHeader full;
  std::string reason;
  if (LoadFile(h.File, format, full, reason, false) != FileKind::Image) {
    error = reason.empty() ? "cannot be read" : reason;
    return false;
  }
  DcmDataset* ds = format.getDataset();
  if (syntax && syntax->Decoder == PixelDecoder::CharLS) {
    const size_t frameBytes = static_cast<size_t>(h.Rows) * h.Columns * static_cast<size_t>(h.BitsAllocated / 8);
    if (!DecodeJpegLsPixels(ds, h.Frames, frameBytes, pixels.Owned, error)) {
      error = TransferSyntaxLabel(h.TransferSyntax) + ": " + error;
      return false;
    }
    pixels.Data = pixels.Owned.data();
    pixels.Bytes = pixels.Owned.size();
    return true;
  }
  if (DcmXfer(ds->getOriginalXfer()).isEncapsulated()) {
    OFCondition c = ds->chooseRepresentation(EXS_LittleEndianExplicit, nullptr);
    if (c.bad() || !ds->canWriteXfer(EXS_LittleEndianExplicit)) {
      error = "cannot decompress pixel data (" + TransferSyntaxLabel(h.TransferSyntax) + ", " + c.text() + ")";
      return false;
    }
  }
  DcmElement* element = nullptr;
  if (ds->findAndGetElement(DCM_FloatPixelData, element).good() && element) {
    Float32* data = nullptr;
    pixels.FloatBits = 32;
    pixels.Bytes = element->getFloat32Array(data).good() && data ? element->getLength() : 0;
    pixels.Data = data;
    return true;
  }
  if (ds->findAndGetElement(DCM_DoubleFloatPixelData, element).good() && element) {
    Float64* data = nullptr;
    pixels.FloatBits = 64;
    pixels.Bytes = element->getFloat64Array(data).good() && data ? element->getLength() : 0;
    pixels.Data = data;
    return true;
  }
  if (ds->findAndGetElement(DCM_PixelData, element).bad() || !element) {
    error = "no pixel data";
    return false;
  }
  // OB as bytes, OW as 16-bit words in this machine's byte order (DCMTK swaps big-endian files
  // word by word, as it writes them: a 32-bit pixel is then whole again in this machine's order).
  OFCondition status;
  if (element->getVR() == EVR_OB || h.BitsAllocated == 8) {
    Uint8* data = nullptr;
    status = element->getUint8Array(data);
    pixels.Data = data;
  } else {
    Uint16* data = nullptr;
    status = element->getUint16Array(data);
    pixels.Data = data;
  }
  pixels.Bytes = status.good() && pixels.Data ? element->getLength() : 0;
  return true;
}

template <typename In, typename Out>
void Narrow(const In* in, Out* out, size_t count) {
  for (size_t i = 0; i < count; ++i) out[i] = static_cast<Out>(in[i]);
}

// A double stack (32/64-bit pixels) → the narrowest type that holds its values exactly:
// short/ushort/int when they are whole numbers in range (integer pixel data only), double for
// Double Float Pixel Data, float otherwise.
vtkSmartPointer<vtkImageData> NarrowWide(vtkImageData* stack, int floatBits) {
  const double* values = static_cast<const double*>(stack->GetScalarPointer());
  const size_t total = static_cast<size_t>(stack->GetNumberOfPoints());
  bool whole = floatBits == 0;
  double lo = 0.0, hi = 0.0;
  for (size_t i = 0; i < total && whole; ++i) {
    whole = values[i] == std::floor(values[i]);
    lo = i == 0 ? values[i] : std::min(lo, values[i]);
    hi = i == 0 ? values[i] : std::max(hi, values[i]);
  }
  int type = floatBits == 64 ? VTK_DOUBLE : VTK_FLOAT;
  if (whole)
    type = (lo >= -32768 && hi <= 32767)   ? VTK_SHORT
           : (lo >= 0 && hi <= 65535)      ? VTK_UNSIGNED_SHORT
           : (lo >= INT32_MIN && hi <= INT32_MAX) ? VTK_INT
                                          : VTK_DOUBLE;
  if (type == VTK_DOUBLE) return stack;
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(stack->GetDimensions());
  image->AllocateScalars(type, 1);
  switch (type) {
    case VTK_SHORT: Narrow(values, static_cast<short*>(image->GetScalarPointer()), total); break;
    case VTK_UNSIGNED_SHORT: Narrow(values, static_cast<unsigned short*>(image->GetScalarPointer()), total); break;
    case VTK_INT: Narrow(values, static_cast<int*>(image->GetScalarPointer()), total); break;
    default: Narrow(values, static_cast<float*>(image->GetScalarPointer()), total); break;
  }
  return image;
}

// An irregular stack resampled along the normal onto a regular grid whose spacing is about the
// smallest gap (linear, float); `positions` and `spacing` receive the new grid's.
vtkSmartPointer<vtkImageData> ResampleAlongNormal(vtkImageData* stack, const SeriesGeometry& g,
                                                  std::vector<double>& positions, double& spacing) {
  int dims[3];
  stack->GetDimensions(dims);
  const size_t sliceSize = static_cast<size_t>(dims[0]) * dims[1];
  spacing = g.MinGap;
  const double length = g.Positions.back() - g.Positions.front();
  const int n = static_cast<int>(std::lround(length / spacing)) + 1;
  spacing = n > 1 ? length / (n - 1) : spacing;
  positions.clear();
  for (int k = 0; k < n; ++k) positions.push_back(g.Positions.front() + k * spacing);
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(dims[0], dims[1], n);
  image->AllocateScalars(VTK_FLOAT, 1);
  float* dst = static_cast<float*>(image->GetScalarPointer());
  vtkDataArray* src = stack->GetPointData()->GetScalars();
  size_t below = 0;
  for (int k = 0; k < n; ++k) {
    const double p = positions[k];
    while (below + 2 < g.Positions.size() && g.Positions[below + 1] <= p) ++below;
    const size_t a = below, b = std::min(below + 1, g.Positions.size() - 1);
    const double t = b != a ? std::clamp((p - g.Positions[a]) / (g.Positions[b] - g.Positions[a]), 0.0, 1.0) : 0.0;
    for (size_t i = 0; i < sliceSize; ++i) {
      const double va = src->GetComponent(static_cast<vtkIdType>(a * sliceSize + i), 0);
      const double vb = src->GetComponent(static_cast<vtkIdType>(b * sliceSize + i), 0);
      dst[static_cast<size_t>(k) * sliceSize + i] = static_cast<float>((1.0 - t) * va + t * vb);
    }
  }
  return image;
}

// An int32 stack narrowed to 16 bits when the values fit (CT in HU, most MR).
vtkSmartPointer<vtkImageData> NarrowInt(vtkImageData* stack) {
  const int* values = static_cast<const int*>(stack->GetScalarPointer());
  const size_t total = static_cast<size_t>(stack->GetNumberOfPoints());
  int lo = std::numeric_limits<int>::max(), hi = std::numeric_limits<int>::min();
  for (size_t i = 0; i < total; ++i) {
    lo = std::min(lo, values[i]);
    hi = std::max(hi, values[i]);
  }
  const int type = (lo >= -32768 && hi <= 32767) ? VTK_SHORT : (lo >= 0 && hi <= 65535) ? VTK_UNSIGNED_SHORT : VTK_INT;
  if (type == VTK_INT) return stack;
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(stack->GetDimensions());
  image->AllocateScalars(type, 1);
  if (type == VTK_SHORT)
    Narrow(values, static_cast<short*>(image->GetScalarPointer()), total);
  else
    Narrow(values, static_cast<unsigned short*>(image->GetScalarPointer()), total);
  return image;
}

// Geometry: i along a row (IOP row direction, column spacing), j down the columns, k along
// the normal; IJK-to-LPS from the first header, its origin moved to `firstPosition` along the
// normal (a resampled grid's first slice).
void StackMatrix(const SliceHeader& h0, const SeriesGeometry& g, double spacing, double firstPosition,
                 double ijkToLPS[16]) {
  double axes[3][3] = {{h0.Orientation[0], h0.Orientation[1], h0.Orientation[2]},
                       {h0.Orientation[3], h0.Orientation[4], h0.Orientation[5]},
                       {g.Normal[0], g.Normal[1], g.Normal[2]}};
  for (int c = 0; c < 2; ++c) {
    const double n = std::sqrt(Dot3(axes[c], axes[c]));
    for (double& v : axes[c]) v /= n;
  }
  const double spacings[3] = {h0.PixelSpacing[1], h0.PixelSpacing[0], spacing};
  double origin[3] = {h0.Position[0], h0.Position[1], h0.Position[2]};
  const double shift = firstPosition - g.Positions.front();
  for (int r = 0; r < 3; ++r) origin[r] += shift * g.Normal[r];
  for (int i = 0; i < 16; ++i) ijkToLPS[i] = i == 15 ? 1.0 : 0.0;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) ijkToLPS[4 * r + c] = axes[c][r] * spacings[c];
    ijkToLPS[4 * r + 3] = origin[r];
  }
}

// The distinct notes of a stack's images, in order (the same note on every slice once).
std::vector<std::string> SeriesNotes(const std::vector<SliceHeader>& headers) {
  std::vector<std::string> notes, keys;
  for (const SliceHeader& h : headers)
    for (const std::string& n : h.Notes) {
      // The same note for another file once only (they differ in the file name).
      std::string key = n;
      const std::string file = Name(h.File);
      if (const size_t at = key.find(file); !file.empty() && at != std::string::npos) key.erase(at, file.size());
      if (std::find(keys.begin(), keys.end(), key) != keys.end()) continue;
      keys.push_back(key);
      notes.push_back(n);
    }
  return notes;
}

// Headers of every image in `files` (one per frame for multi-frame files).
bool ReadHeaders(const std::vector<std::string>& files, std::vector<SliceHeader>& headers, std::string& error) {
  for (const std::string& file : files) {
    DcmFileFormat format;
    SliceHeader h;
    std::string reason;
    const FileKind kind = LoadFile(file, format, h, reason, true);
    if (kind != FileKind::Image) {
      error = file + ": " + (kind == FileKind::Corrupt ? reason : std::string("not a DICOM image"));
      return false;
    }
    ExpandFrames(format, h, headers);
  }
  return true;
}

}  // namespace

bool ScanDicom(const std::string& path, DicomScanResult& result, std::string& error, const ProgressCallback& progress) {
  InitializeDcmtk();
  result = DicomScanResult();
  std::vector<std::string> files;
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
  } else if (fs::is_regular_file(root, ec)) {
    // A DICOMDIR: read its image records; any other file is scanned on its own.
    DcmFileFormat probe;
    bool isDicomDir = false;
    if (probe.loadFileUntilTag(path.c_str(), EXS_Unknown, EGL_noChange, DCM_MaxReadLength, ERM_autoDetect,
                               DCM_PixelData)
            .good()) {
      isDicomDir = GetString(probe.getMetaInfo(), DCM_MediaStorageSOPClassUID) == UID_MediaStorageDirectoryStorage;
    }
    if (isDicomDir) {
      DcmDicomDir dir(path.c_str());
      if (dir.error().bad()) {
        error = "cannot read DICOMDIR " + path + ": " + dir.error().text();
        return false;
      }
      const fs::path base = root.parent_path();
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
    } else {
      files.push_back(path);
    }
  } else {
    error = "no such file or folder: " + path;
    return false;
  }

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
      case FileKind::NonImage: ++result.NonImageDicomFiles; break;
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
    for (size_t s = 0; s < stacks.size(); ++s) {
      const std::vector<SliceHeader>& headers = stacks[s];
      DicomSeriesInfo info;
      const SliceHeader& h = headers.front();
      info.SeriesInstanceUID = uid;
      info.StackIndex = static_cast<int>(s) + 1;
      info.StackCount = static_cast<int>(stacks.size());
      info.StackID = stacks.size() == 1 ? uid : uid + "#" + std::to_string(s + 1);
      info.StudyInstanceUID = h.StudyUID;
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
      info.CorruptFiles = corruptBySeries[uid];
      if (!info.CorruptFiles.empty()) info.Problem = "corrupt or truncated file " + info.CorruptFiles.front();
      result.Series.push_back(std::move(info));
    }
  }
  return true;
}

bool ReadDicomSeries(const DicomSeriesInfo& series, ImageVolume& volume, std::string& error,
                     const DicomReadOptions& options, std::vector<std::string>* warnings,
                     const ProgressCallback& progress) {
  InitializeDcmtk();
  const std::string what = "DICOM series " + (series.StackID.empty() ? series.SeriesInstanceUID : series.StackID);
  try {
    if (series.Files.empty()) {
      error = what + " has no files";
      return false;
    }
    if (!series.CorruptFiles.empty()) {
      error = what + ": corrupt or truncated file " + series.CorruptFiles.front();
      return false;
    }
    // Headers first (cheap): refuse bad geometry before decoding any pixels. Only the images of
    // this stack count (a file list may hold frames of other stacks).
    std::vector<SliceHeader> all, headers;
    if (!ReadHeaders(series.Files, all, error)) return false;
    SliceHeader key;
    key.Rows = series.Rows;
    key.Columns = series.Columns;
    key.HasOrientation = all.front().HasOrientation;
    std::copy(series.Orientation, series.Orientation + 6, key.Orientation);
    std::copy(series.PixelSpacing, series.PixelSpacing + 2, key.PixelSpacing);
    for (SliceHeader& h : all)
      if (series.Rows == 0 || SameStack(key, h)) headers.push_back(std::move(h));
    if (headers.empty()) {
      error = what + ": no image of " + std::to_string(series.Columns) + "x" + std::to_string(series.Rows) +
              " pixels in the orientation scanned (the files changed since the scan?)";
      return false;
    }
    if (series.Rows == 0 && SplitIntoStacks(headers).size() > 1) {
      error = what + ": the files hold several stacks (orientations or image sizes); scan them to choose one";
      return false;
    }
    const SeriesGeometry g = AnalyzeGeometry(headers, options.SpacingTolerance);
    if (!g.Problem.empty()) {
      error = what + ": " + g.Problem;
      return false;
    }
    if (g.Irregular && !options.ResampleIrregularSpacing) {
      error = what + ": " + g.IrregularMessage + " (refused; allow resampling to load it with its true geometry)";
      return false;
    }
    // Decode every image in geometric order into a stack: int32 when every image's slope and
    // intercept are integers (exact), float otherwise; narrowed to short/ushort afterwards.
    const int cols = headers.front().Columns, rows = headers.front().Rows;
    const size_t sliceSize = static_cast<size_t>(cols) * rows;
    bool integral = true;
    for (const SliceHeader& h : headers)
      integral = integral && h.Slope == std::floor(h.Slope) && h.Intercept == std::floor(h.Intercept) &&
                 std::abs(h.Slope) < 65536 && std::abs(h.Intercept) < 1e9;
    const int stackDepth = static_cast<int>(g.Order.size());
    // 32- and 64-bit pixels (integer or float) go through a double stack: exact for every
    // 32-bit integer times an integer slope; narrowed below.
    const bool wide = std::any_of(headers.begin(), headers.end(), [](const SliceHeader& h) { return h.BitsAllocated >= 32; });
    const int stackType = wide ? VTK_DOUBLE : integral ? VTK_INT : VTK_FLOAT;
    // The stack, the narrowed (or resampled) copy beside it, and one decoded file.
    const int64_t dims[3] = {cols, rows, stackDepth};
    if (!CheckImageFitsInMemory(dims, wide ? 8.0 : 4.0, what, error, g.Irregular ? 2.0 : 1.5)) return false;
    auto stack = vtkSmartPointer<vtkImageData>::New();
    stack->SetDimensions(cols, rows, stackDepth);
    stack->AllocateScalars(stackType, 1);
    int floatBits = 0;  // of float pixel data, if any
    // Each file is decoded once, all its frames at a time, in the order of its first image.
    std::vector<size_t> sliceOfHeader(headers.size());
    for (size_t k = 0; k < g.Order.size(); ++k) sliceOfHeader[g.Order[k]] = k;
    std::vector<std::string> fileOrder;
    std::map<std::string, std::vector<size_t>> headersOfFile;
    for (size_t k = 0; k < g.Order.size(); ++k) {
      const std::string& file = headers[g.Order[k]].File;
      if (!headersOfFile.count(file)) fileOrder.push_back(file);
      headersOfFile[file].push_back(g.Order[k]);
    }
    size_t done = 0;
    for (const std::string& file : fileOrder) {
      const std::vector<size_t>& indices = headersOfFile[file];
      DcmFileFormat format;
      DecodedPixels pixels;
      if (!DecodeFile(headers[indices.front()], format, pixels, error)) {
        error = file + ": " + error;
        return false;
      }
      for (size_t index : indices) {
        const SliceHeader& h = headers[index];
        const size_t k = sliceOfHeader[index];
        floatBits = std::max(floatBits, pixels.FloatBits);
        void* slice = stack->GetScalarPointer();
        const bool ok =
            stackType == VTK_DOUBLE ? ConvertFrame(pixels, h, static_cast<double*>(slice) + k * sliceSize, error)
            : stackType == VTK_INT  ? ConvertFrame(pixels, h, static_cast<int*>(slice) + k * sliceSize, error)
                                    : ConvertFrame(pixels, h, static_cast<float*>(slice) + k * sliceSize, error);
        if (!ok) {
          error = file + ": " + error;
          return false;
        }
        ++done;
        if (progress) progress(double(done) / g.Order.size(), "reading DICOM");
      }
    }
    // Irregular series: resample along the normal onto a regular grid (linear, float);
    // otherwise narrow the stack to the smallest type that holds its values.
    std::vector<double> outPositions = g.Positions;
    double spacing = g.Spacing;
    vtkSmartPointer<vtkImageData> image = stack;
    if (g.Irregular) {
      image = ResampleAlongNormal(stack, g, outPositions, spacing);
      if (warnings)
        warnings->push_back(g.IrregularMessage + "; resampled to " + std::to_string(outPositions.size()) + " slices " +
                            Fmt(spacing, 3) + " mm apart by linear interpolation along the slice normal");
    } else if (stackType == VTK_DOUBLE) {
      image = NarrowWide(stack, floatBits);
    } else if (stackType == VTK_INT) {
      image = NarrowInt(stack);
    }
    const SliceHeader& h0 = headers[g.Order.front()];
    double ijkToLPS[16];
    StackMatrix(h0, g, spacing, outPositions.front(), ijkToLPS);
    FlipLPSRASIndexToSpace(ijkToLPS);
    ImageVolume result;
    result.Image = image;
    result.IJKToRAS->DeepCopy(ijkToLPS);
    if (h0.HasWindow) {
      result.Window = h0.WindowWidth;
      result.Level = h0.WindowCenter;
    }
    result.Modality = h0.Modality;
    result.Description = h0.Description;
    if (warnings) {
      if (!h0.HasPixelSpacing && h0.Notes.empty())
        warnings->push_back("no PixelSpacing in " + Name(h0.File) + ": 1 mm pixels assumed");
      for (const std::string& note : SeriesNotes(headers)) warnings->push_back(note);
    }
    if (warnings && h0.Photometric == "MONOCHROME1")
      warnings->push_back("MONOCHROME1 series: values are kept as stored (low = white on the scanner display)");
    if (warnings) {
      const TransferSyntaxInfo* syntax = FindTransferSyntax(h0.TransferSyntax);
      if (syntax && !syntax->Lossless)
        warnings->push_back("lossy compressed (" + syntax->Name + "): voxel values differ from the acquired ones");
    }
    volume = result;
    return true;
  } catch (const std::bad_alloc&) {
    error = what + ": out of memory";
  } catch (const std::exception& e) {
    error = what + ": " + e.what();
  }
  return false;
}

bool ReadDicomVolume(const std::string& path, ImageVolume& volume, std::string& error, const std::string& seriesID,
                     const DicomReadOptions& options, std::vector<std::string>* warnings,
                     const ProgressCallback& progress) {
  DicomScanResult scan;
  if (!ScanDicom(path, scan, error, progress)) return false;
  auto listing = [](const std::vector<const DicomSeriesInfo*>& stacks) {
    std::string text;
    for (const DicomSeriesInfo* s : stacks) {
      text += (text.empty() ? "" : "; ") + s->StackID + " (" + s->OrientationName + ", " + std::to_string(s->Columns) +
              "x" + std::to_string(s->Rows) + "x" + std::to_string(s->Slices) +
              (s->SeriesDescription.empty() ? "" : ", \"" + s->SeriesDescription + "\"") + ")";
    }
    return text;
  };
  std::vector<const DicomSeriesInfo*> matches;
  for (const auto& s : scan.Series)
    if (seriesID.empty() || s.StackID == seriesID || s.SeriesInstanceUID == seriesID) matches.push_back(&s);
  if (matches.empty()) {
    error = seriesID.empty() ? "no DICOM image series in " + path + " (" + std::to_string(scan.FilesExamined) +
                                   " files examined, " + std::to_string(scan.NonDicomFiles) + " not DICOM" +
                                   (scan.CorruptFiles.empty() ? "" : ", corrupt: " + scan.CorruptFiles.front()) + ")"
                             : "no series " + seriesID + " in " + path;
    return false;
  }
  if (matches.size() > 1) {
    const bool oneSeries = std::all_of(matches.begin(), matches.end(), [&](const DicomSeriesInfo* s) {
      return s->SeriesInstanceUID == matches.front()->SeriesInstanceUID;
    });
    error = oneSeries ? "DICOM series " + matches.front()->SeriesInstanceUID + " holds " +
                            std::to_string(matches.size()) + " stacks of different orientations or sizes: " +
                            listing(matches) + "; choose one by its ID"
                      : path + " holds " + std::to_string(matches.size()) + " DICOM series or stacks: " +
                            listing(matches) + "; choose one by its ID";
    return false;
  }
  const DicomSeriesInfo* chosen = matches.front();
  if (warnings) {
    if (scan.NonDicomFiles > 0)
      warnings->push_back(std::to_string(scan.NonDicomFiles) + " non-DICOM file(s) skipped");
    for (const auto& c : scan.CorruptFiles) warnings->push_back("skipped " + c);
  }
  if (ReadDicomSeries(*chosen, volume, error, options, warnings, progress)) return true;
  if (!scan.CorruptFiles.empty() && chosen->CorruptFiles.empty())
    error += " (also skipped as corrupt or truncated: " + scan.CorruptFiles.front() + ")";
  return false;
}

}  // namespace rp
