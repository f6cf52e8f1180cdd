// Reading one DICOM stack into a volume (rpDicomSeries.h): the stack's headers checked, every
// file decoded once (rpDicomPixels.h) into a stack in geometric order (rpDicomGeometry.h), then
// narrowed, or resampled when the spacing is irregular and that was asked for.
#include "rpDicomSeries.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <new>
#include <stdexcept>

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dctk.h>

#include <vtkImageData.h>

#include "rpDicomCommon.h"
#include "rpDicomGeometry.h"
#include "rpDicomHeader.h"
#include "rpDicomPixels.h"
#include "rpDicomTransferSyntax.h"
#include "rpLPSRAS.h"
#include "rpMemoryBudget.h"

namespace rp {

namespace {

using namespace dicom;

// The headers of the images of this stack (a file list may hold frames of other stacks), read
// first (cheap) so that bad geometry is refused before any pixel is decoded.
bool StackHeaders(const DicomSeriesInfo& series, const std::string& what, std::vector<SliceHeader>& headers,
                  std::string& error) {
  if (series.Files.empty()) {
    error = what + " has no files";
    return false;
  }
  if (!series.CorruptFiles.empty()) {
    error = what + ": corrupt or truncated file " + series.CorruptFiles.front();
    return false;
  }
  std::vector<SliceHeader> all;
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
  return true;
}

// The stack's scalar type: 32- and 64-bit pixels (integer or float) go through doubles (exact
// for every 32-bit integer times an integer slope), others through int32 when every image's
// slope and intercept are integers (exact), float otherwise; narrowed afterwards.
int StackType(const std::vector<SliceHeader>& headers) {
  bool integral = true;
  for (const SliceHeader& h : headers)
    integral = integral && h.Slope == std::floor(h.Slope) && h.Intercept == std::floor(h.Intercept) &&
               std::abs(h.Slope) < 65536 && std::abs(h.Intercept) < 1e9;
  const bool wide = std::any_of(headers.begin(), headers.end(), [](const SliceHeader& h) { return h.BitsAllocated >= 32; });
  return wide ? VTK_DOUBLE : integral ? VTK_INT : VTK_FLOAT;
}

// Decodes every image into `stack` (slice k = the k-th along the normal). Each file is decoded
// once, all its frames at a time, in the order of its first image. `floatBits`: of float pixel
// data, if any.
bool DecodeStack(const std::vector<SliceHeader>& headers, const SeriesGeometry& g, vtkImageData* stack, int& floatBits,
                 std::string& error, const ProgressCallback& progress) {
  const size_t sliceBytes = static_cast<size_t>(headers.front().Columns) * headers.front().Rows *
                            static_cast<size_t>(stack->GetScalarSize());
  std::vector<size_t> sliceOfHeader(headers.size());
  for (size_t k = 0; k < g.Order.size(); ++k) sliceOfHeader[g.Order[k]] = k;
  std::vector<std::string> fileOrder;
  std::map<std::string, std::vector<size_t>> headersOfFile;
  for (size_t k = 0; k < g.Order.size(); ++k) {
    const std::string& file = headers[g.Order[k]].File;
    if (!headersOfFile.count(file)) fileOrder.push_back(file);
    headersOfFile[file].push_back(g.Order[k]);
  }
  floatBits = 0;
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
      floatBits = std::max(floatBits, pixels.FloatBits);
      char* slice = static_cast<char*>(stack->GetScalarPointer()) + sliceOfHeader[index] * sliceBytes;
      if (!ConvertFrame(pixels, headers[index], stack->GetScalarType(), slice, error)) {
        error = file + ": " + error;
        return false;
      }
      ++done;
      if (progress) progress(double(done) / g.Order.size(), "reading DICOM");
    }
  }
  return true;
}

// What the reader assumed or ignored, for the caller's warnings.
void AddReadWarnings(const std::vector<SliceHeader>& headers, const SliceHeader& h0, std::vector<std::string>& warnings) {
  if (!h0.HasPixelSpacing && h0.Notes.empty())
    warnings.push_back("no PixelSpacing in " + Name(h0.File) + ": 1 mm pixels assumed");
  for (const std::string& note : SeriesNotes(headers)) warnings.push_back(note);
  if (h0.Photometric == "MONOCHROME1")
    warnings.push_back("MONOCHROME1 series: values are kept as stored (low = white on the scanner display)");
  const TransferSyntaxInfo* syntax = FindTransferSyntax(h0.TransferSyntax);
  if (syntax && !syntax->Lossless)
    warnings.push_back("lossy compressed (" + syntax->Name + "): voxel values differ from the acquired ones");
}

bool ReadStack(const DicomSeriesInfo& series, const std::string& what, ImageVolume& volume, std::string& error,
               const DicomReadOptions& options, std::vector<std::string>* warnings, const ProgressCallback& progress) {
  std::vector<SliceHeader> headers;
  if (!StackHeaders(series, what, headers, error)) return false;
  const SeriesGeometry g = AnalyzeGeometry(headers, options.SpacingTolerance);
  if (!g.Problem.empty()) {
    error = what + ": " + g.Problem;
    return false;
  }
  if (g.Irregular && !options.ResampleIrregularSpacing) {
    error = what + ": " + g.IrregularMessage + " (refused; allow resampling to load it with its true geometry)";
    return false;
  }
  const int stackType = StackType(headers);
  // The stack, the narrowed (or resampled) copy beside it, and one decoded file.
  const int cols = headers.front().Columns, rows = headers.front().Rows, depth = static_cast<int>(g.Order.size());
  const int64_t dims[3] = {cols, rows, depth};
  if (!CheckImageFitsInMemory(dims, stackType == VTK_DOUBLE ? 8.0 : 4.0, what, error, g.Irregular ? 2.0 : 1.5))
    return false;
  auto stack = vtkSmartPointer<vtkImageData>::New();
  stack->SetDimensions(cols, rows, depth);
  stack->AllocateScalars(stackType, 1);
  int floatBits = 0;
  if (!DecodeStack(headers, g, stack, floatBits, error, progress)) return false;
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
  if (warnings) AddReadWarnings(headers, h0, *warnings);
  volume = result;
  return true;
}

// "<ID> (orientation, size, "description"); ..." for a refusal that names the choices.
std::string Listing(const std::vector<const DicomSeriesInfo*>& stacks) {
  std::string text;
  for (const DicomSeriesInfo* s : stacks) {
    text += (text.empty() ? "" : "; ") + s->StackID + " (" + s->OrientationName + ", " + std::to_string(s->Columns) +
            "x" + std::to_string(s->Rows) + "x" + std::to_string(s->Slices) +
            (s->SeriesDescription.empty() ? "" : ", \"" + s->SeriesDescription + "\"") + ")";
  }
  return text;
}

}  // namespace

bool ReadDicomSeries(const DicomSeriesInfo& series, ImageVolume& volume, std::string& error,
                     const DicomReadOptions& options, std::vector<std::string>* warnings,
                     const ProgressCallback& progress) {
  InitializeDcmtk();
  const std::string what = "DICOM series " + (series.StackID.empty() ? series.SeriesInstanceUID : series.StackID);
  try {
    return ReadStack(series, what, volume, error, options, warnings, progress);
  } catch (const std::bad_alloc&) {
    error = what + ": out of memory";
  } catch (const std::exception& e) {
    error = what + ": " + e.what();
  }
  return false;
}

const DicomSeriesInfo* ChooseDicomStack(const DicomScanResult& scan, const std::string& path,
                                        const std::string& seriesID, std::string& error) {
  std::vector<const DicomSeriesInfo*> matches;
  for (const auto& s : scan.Series)
    if (seriesID.empty() || s.StackID == seriesID || s.SeriesInstanceUID == seriesID) matches.push_back(&s);
  if (matches.empty()) {
    error = seriesID.empty() ? "no DICOM image series in " + path + " (" + std::to_string(scan.FilesExamined) +
                                   " files examined, " + std::to_string(scan.NonDicomFiles) + " not DICOM" +
                                   (scan.CorruptFiles.empty() ? "" : ", corrupt: " + scan.CorruptFiles.front()) + ")"
                             : "no series " + seriesID + " in " + path;
    return nullptr;
  }
  if (matches.size() > 1) {
    const bool oneSeries = std::all_of(matches.begin(), matches.end(), [&](const DicomSeriesInfo* s) {
      return s->SeriesInstanceUID == matches.front()->SeriesInstanceUID;
    });
    error = oneSeries ? "DICOM series " + matches.front()->SeriesInstanceUID + " holds " +
                            std::to_string(matches.size()) + " stacks of different orientations or sizes: " +
                            Listing(matches) + "; choose one by its ID"
                      : path + " holds " + std::to_string(matches.size()) + " DICOM series or stacks: " +
                            Listing(matches) + "; choose one by its ID";
    return nullptr;
  }
  return matches.front();
}

bool ReadDicomVolume(const std::string& path, ImageVolume& volume, std::string& error, const std::string& seriesID,
                     const DicomReadOptions& options, std::vector<std::string>* warnings,
                     const ProgressCallback& progress) {
  DicomScanResult scan;
  if (!ScanDicom(path, scan, error, progress)) return false;
  const DicomSeriesInfo* chosen = ChooseDicomStack(scan, path, seriesID, error);
  if (!chosen) return false;
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
