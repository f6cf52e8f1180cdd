#pragma once
// Internal to RoboPlanDicom: one DICOM image's header as the series reader needs it (a
// single-frame file, or one frame of a multi-frame file), read with DCMTK. Scanning
// (rpDicomScan.cxx), geometry (rpDicomGeometry.h), pixel decoding (rpDicomPixels.h) and reading
// (rpDicomSeries.cxx) share it.
#include <cstdint>
#include <string>
#include <vector>

class DcmFileFormat;
class DcmItem;
class DcmTagKey;

namespace rp::dicom {

enum class FileKind { Image, NonImage, NotDicom, Corrupt };

// One image: a single-frame file, or one frame of a multi-frame file.
struct SliceHeader {
  std::string File;
  int Frame = 0;  // index of the frame in its file
  std::string SeriesUID, StudyUID, FrameOfReferenceUID, Modality, Description, PatientName, SeriesNumber, TransferSyntax;
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

/// A string attribute with trailing spaces and NULs removed ("" when absent).
std::string GetString(DcmItem* item, const DcmTagKey& tag);
/// `count` numbers of a multi-valued attribute; false when any is missing.
bool GetDoubles(DcmItem* item, const DcmTagKey& tag, double* values, int count);
/// An integer attribute (US, SL or text), else `fallback`.
int GetInt(DcmItem* item, const DcmTagKey& tag, int fallback);
/// The file name of a path (for messages).
std::string Name(const std::string& path);
/// A number with `precision` decimals (for messages).
std::string Fmt(double v, int precision = 2);

/// Loads a file (only up to the pixel data when `headerOnly`) and classifies it; for an image
/// (and a segmentation object) `h` holds its header, for a corrupt file `reason` says why.
FileKind LoadFile(const std::string& path, DcmFileFormat& format, SliceHeader& h, std::string& reason,
                  bool headerOnly);
/// One header per image of the file: itself, or one per frame of a multi-frame file (with the
/// frame's functional groups, or its legacy multi-frame geometry, applied).
void ExpandFrames(DcmFileFormat& format, const SliceHeader& file, std::vector<SliceHeader>& out);
/// Headers of every image in `files` (one per frame for multi-frame files).
bool ReadHeaders(const std::vector<std::string>& files, std::vector<SliceHeader>& headers, std::string& error);
/// The distinct notes of a stack's images, in order (the same note on every slice once).
std::vector<std::string> SeriesNotes(const std::vector<SliceHeader>& headers);

}  // namespace rp::dicom
