#include "rpDicomWriter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <limits>
#include <vector>

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dctk.h>

#include <vtkDataArray.h>
#include <vtkPointData.h>

#include "rpDicomCommon.h"
#include "rpLPSRAS.h"

namespace fs = std::filesystem;

namespace rp {
namespace {

std::string NewUID(const char* root) {
  char buffer[100];
  dcmGenerateUniqueIdentifier(buffer, root);
  return buffer;
}

// DICOM DS values are at most 16 characters: keep as many digits as fit.
std::string DS(double v) {
  if (std::abs(v) < 1e-12) v = 0.0;
  char buffer[64];
  for (int precision = 14; precision >= 4; --precision) {
    std::snprintf(buffer, sizeof buffer, "%.*g", precision, v);
    if (std::strlen(buffer) <= 16) return buffer;
  }
  std::snprintf(buffer, sizeof buffer, "%.6e", v);
  return buffer;
}

std::string Join(std::initializer_list<double> values) {
  std::string s;
  for (double v : values) s += (s.empty() ? "" : "\\") + DS(v);
  return s;
}

struct Quantization {
  bool Signed = true;
  double Slope = 1.0, Intercept = 0.0;
  double MaxError = 0.0;
};

Quantization ChooseQuantization(vtkDataArray* scalars) {
  Quantization q;
  const vtkIdType n = scalars->GetNumberOfTuples();
  double lo = std::numeric_limits<double>::max(), hi = -lo;
  bool integral = true;
  for (vtkIdType i = 0; i < n; ++i) {
    const double v = scalars->GetComponent(i, 0);
    lo = std::min(lo, v);
    hi = std::max(hi, v);
    integral = integral && v == std::floor(v);
  }
  if (n == 0) lo = hi = 0.0;
  if (integral && lo >= -32768 && hi <= 32767) return q;  // signed 16, identity
  if (integral && lo >= 0 && hi <= 65535) {
    q.Signed = false;
    return q;
  }
  if (integral && hi - lo <= 65535) {
    q.Signed = false;
    q.Intercept = lo;
    return q;
  }
  // Lossy: spread the range over 16 bits.
  q.Signed = false;
  q.Intercept = lo;
  q.Slope = hi > lo ? (hi - lo) / 65535.0 : 1.0;
  // DS strings keep ~14 digits; use the written values so the error is the real one.
  q.Slope = std::stod(DS(q.Slope));
  q.Intercept = std::stod(DS(q.Intercept));
  return q;
}

}  // namespace

bool WriteDicomSeries(const ImageVolume& volume, const std::string& folder, const DicomWriteOptions& options,
                      std::string& error, DicomWriteResult* result, const ProgressCallback& progress) {
  InitializeDcmtk();
  if (volume.Empty()) {
    error = "cannot write an empty volume as DICOM";
    return false;
  }
  vtkDataArray* scalars = volume.Image->GetPointData()->GetScalars();
  if (!scalars || scalars->GetNumberOfComponents() != 1) {
    error = "DICOM writer: only single-component (scalar) volumes are supported";
    return false;
  }
  const bool mr = options.Modality == "MR";
  if (!mr && options.Modality != "CT") {
    error = "DICOM writer: modality must be CT or MR (got '" + options.Modality + "')";
    return false;
  }
  int dims[3];
  volume.Image->GetDimensions(dims);
  if (dims[0] > 65535 || dims[1] > 65535) {
    error = "DICOM writer: image too large for Rows/Columns";
    return false;
  }

  // Geometry in LPS.
  double ijkToLPS[16];
  std::copy(volume.IJKToRAS->GetData(), volume.IJKToRAS->GetData() + 16, ijkToLPS);
  FlipLPSRASIndexToSpace(ijkToLPS);
  double axis[3][3], spacing[3], origin[3];
  for (int c = 0; c < 3; ++c) {
    double len = 0.0;
    for (int r = 0; r < 3; ++r) {
      axis[c][r] = ijkToLPS[4 * r + c];
      len += axis[c][r] * axis[c][r];
    }
    spacing[c] = std::sqrt(len);
    if (spacing[c] <= 0.0) {
      error = "DICOM writer: IJK-to-RAS matrix has a zero column";
      return false;
    }
    for (double& v : axis[c]) v /= spacing[c];
  }
  for (int r = 0; r < 3; ++r) origin[r] = ijkToLPS[4 * r + 3];
  auto dot = [](const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  if (std::abs(dot(axis[0], axis[1])) > 1e-4 || std::abs(dot(axis[0], axis[2])) > 1e-4 ||
      std::abs(dot(axis[1], axis[2])) > 1e-4) {
    error = "DICOM writer: the volume's axes are not perpendicular (sheared grid); resample it first";
    return false;
  }
  const double normal[3] = {axis[0][1] * axis[1][2] - axis[0][2] * axis[1][1],
                            axis[0][2] * axis[1][0] - axis[0][0] * axis[1][2],
                            axis[0][0] * axis[1][1] - axis[0][1] * axis[1][0]};
  const bool reversed = dot(normal, axis[2]) < 0.0;

  const Quantization q = ChooseQuantization(scalars);
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (!fs::is_directory(folder)) {
    error = "DICOM writer: cannot create folder " + folder + (ec ? ": " + ec.message() : "");
    return false;
  }

  const std::string studyUID = options.StudyInstanceUID.empty() ? NewUID(SITE_STUDY_UID_ROOT) : options.StudyInstanceUID;
  const std::string seriesUID = NewUID(SITE_SERIES_UID_ROOT);
  const std::string frameUID =
      options.FrameOfReferenceUID.empty() ? NewUID(SITE_SERIES_UID_ROOT) : options.FrameOfReferenceUID;
  char date[16], timeText[16];
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  std::strftime(date, sizeof date, "%Y%m%d", &tm);
  std::strftime(timeText, sizeof timeText, "%H%M%S", &tm);

  const size_t sliceSize = static_cast<size_t>(dims[0]) * dims[1];
  std::vector<Uint16> pixels(sliceSize);
  double maxError = 0.0;
  for (int file = 0; file < dims[2]; ++file) {
    const int k = reversed ? dims[2] - 1 - file : file;
    for (size_t i = 0; i < sliceSize; ++i) {
      const double v = scalars->GetComponent(static_cast<vtkIdType>(k) * sliceSize + i, 0);
      const double stored = std::round((v - q.Intercept) / q.Slope);
      if (q.Signed) {
        pixels[i] = static_cast<Uint16>(static_cast<Sint16>(std::clamp(stored, -32768.0, 32767.0)));
      } else {
        pixels[i] = static_cast<Uint16>(std::clamp(stored, 0.0, 65535.0));
      }
      maxError = std::max(maxError, std::abs(stored * q.Slope + q.Intercept - v));
    }
    double position[3];
    for (int r = 0; r < 3; ++r) position[r] = origin[r] + k * spacing[2] * axis[2][r];

    DcmFileFormat format;
    DcmDataset* ds = format.getDataset();
    const std::string instanceUID = NewUID(SITE_INSTANCE_UID_ROOT);
    const char* sopClass = mr ? UID_MRImageStorage : UID_CTImageStorage;
    OFCondition c = EC_Normal;
    auto put = [&](const DcmTagKey& tag, const std::string& value) {
      if (c.good()) c = ds->putAndInsertString(tag, value.c_str());
    };
    auto put16 = [&](const DcmTagKey& tag, Uint16 value) {
      if (c.good()) c = ds->putAndInsertUint16(tag, value);
    };
    put(DCM_SpecificCharacterSet, "ISO_IR 100");
    put(DCM_ImageType, "DERIVED\\SECONDARY\\AXIAL");
    put(DCM_SOPClassUID, sopClass);
    put(DCM_SOPInstanceUID, instanceUID);
    put(DCM_StudyDate, date);
    put(DCM_SeriesDate, date);
    put(DCM_ContentDate, date);
    put(DCM_StudyTime, timeText);
    put(DCM_SeriesTime, timeText);
    put(DCM_ContentTime, timeText);
    put(DCM_AccessionNumber, "");
    put(DCM_Modality, mr ? "MR" : "CT");
    put(DCM_Manufacturer, "RoboPlan");
    put(DCM_ReferringPhysicianName, "");
    put(DCM_SeriesDescription, options.SeriesDescription.empty() ? volume.Description : options.SeriesDescription);
    put(DCM_PatientName, options.PatientName);
    put(DCM_PatientID, options.PatientID);
    put(DCM_PatientBirthDate, "");
    put(DCM_PatientSex, "O");
    put(DCM_BodyPartExamined, "KNEE");
    put(DCM_SliceThickness, DS(spacing[2]));
    if (mr) {
      put(DCM_ScanningSequence, "SE");
      put(DCM_SequenceVariant, "NONE");
      put(DCM_ScanOptions, "");
      put(DCM_MRAcquisitionType, "2D");
      put(DCM_RepetitionTime, "2500");
      put(DCM_EchoTime, "30");
      put(DCM_EchoTrainLength, "1");
      put(DCM_SpacingBetweenSlices, DS(spacing[2]));
    } else {
      put(DCM_KVP, "120");
    }
    put(DCM_PatientPosition, "FFS");
    put(DCM_StudyInstanceUID, studyUID);
    put(DCM_SeriesInstanceUID, seriesUID);
    put(DCM_StudyID, "1");
    put(DCM_SeriesNumber, std::to_string(options.SeriesNumber));
    put(DCM_AcquisitionNumber, "1");
    put(DCM_InstanceNumber, std::to_string(file + 1));
    put(DCM_ImagePositionPatient, Join({position[0], position[1], position[2]}));
    put(DCM_ImageOrientationPatient,
        Join({axis[0][0], axis[0][1], axis[0][2], axis[1][0], axis[1][1], axis[1][2]}));
    put(DCM_FrameOfReferenceUID, frameUID);
    put(DCM_PositionReferenceIndicator, "");
    put(DCM_SliceLocation, DS(dot(position, normal)));
    put16(DCM_SamplesPerPixel, 1);
    put(DCM_PhotometricInterpretation, "MONOCHROME2");
    put16(DCM_Rows, static_cast<Uint16>(dims[1]));
    put16(DCM_Columns, static_cast<Uint16>(dims[0]));
    put(DCM_PixelSpacing, Join({spacing[1], spacing[0]}));  // row spacing \ column spacing
    put16(DCM_BitsAllocated, 16);
    put16(DCM_BitsStored, 16);
    put16(DCM_HighBit, 15);
    put16(DCM_PixelRepresentation, q.Signed ? 1 : 0);
    if (volume.Window > 0.0) {
      put(DCM_WindowCenter, DS(volume.Level));
      put(DCM_WindowWidth, DS(volume.Window));
    }
    put(DCM_RescaleIntercept, DS(q.Intercept));
    put(DCM_RescaleSlope, DS(q.Slope));
    put(DCM_RescaleType, mr ? "US" : "HU");
    if (c.good()) c = ds->putAndInsertUint16Array(DCM_PixelData, pixels.data(), static_cast<unsigned long>(sliceSize));
    char name[64];
    std::snprintf(name, sizeof name, "%s%05d.dcm", options.FilePrefix.c_str(), file + 1);
    const std::string path = (fs::path(folder) / name).string();
    if (c.good()) c = format.saveFile(path.c_str(), EXS_LittleEndianExplicit);
    if (c.bad()) {
      error = "DICOM writer: cannot write " + path + ": " + c.text();
      return false;
    }
    if (progress) progress(double(file + 1) / dims[2], "writing DICOM");
  }
  if (result) {
    result->SeriesInstanceUID = seriesUID;
    result->StudyInstanceUID = studyUID;
    result->FilesWritten = dims[2];
    result->MaxQuantizationError = maxError;
  }
  return true;
}

}  // namespace rp
