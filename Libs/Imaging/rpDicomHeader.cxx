#include "rpDicomHeader.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dctk.h>

namespace fs = std::filesystem;

namespace rp::dicom {

namespace {

bool HasPart10Preamble(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char buffer[132];
  if (!in.read(buffer, 132)) return false;
  return std::memcmp(buffer + 128, "DICM", 4) == 0;
}

}  // namespace

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

namespace {

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
  h.FrameOfReferenceUID = GetString(ds, DCM_FrameOfReferenceUID);
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

}  // namespace

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

std::string Fmt(double v, int precision) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(precision);
  s << v;
  return s.str();
}

std::string Name(const std::string& path) { return fs::path(path).filename().string(); }

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

}  // namespace rp::dicom
