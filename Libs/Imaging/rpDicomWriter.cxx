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

// The volume's grid in LPS: unit axes (columns of IJK-to-LPS), spacing, origin and slice normal.
struct VolumeGrid {
  double Axis[3][3], Spacing[3], Origin[3], Normal[3];
  bool Reversed = false;  // slice order runs against the row x column normal
};

double Dot(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

bool ComputeVolumeGrid(const ImageVolume& volume, VolumeGrid& g, std::string& error) {
  double ijkToLPS[16];
  std::copy(volume.IJKToRAS->GetData(), volume.IJKToRAS->GetData() + 16, ijkToLPS);
  FlipLPSRASIndexToSpace(ijkToLPS);
  for (int c = 0; c < 3; ++c) {
    double len = 0.0;
    for (int r = 0; r < 3; ++r) {
      g.Axis[c][r] = ijkToLPS[4 * r + c];
      len += g.Axis[c][r] * g.Axis[c][r];
    }
    g.Spacing[c] = std::sqrt(len);
    if (g.Spacing[c] <= 0.0) {
      error = "DICOM writer: IJK-to-RAS matrix has a zero column";
      return false;
    }
    for (double& v : g.Axis[c]) v /= g.Spacing[c];
  }
  for (int r = 0; r < 3; ++r) g.Origin[r] = ijkToLPS[4 * r + 3];
  const auto& axis = g.Axis;
  if (std::abs(Dot(axis[0], axis[1])) > 1e-4 || std::abs(Dot(axis[0], axis[2])) > 1e-4 ||
      std::abs(Dot(axis[1], axis[2])) > 1e-4) {
    error = "DICOM writer: the volume's axes are not perpendicular (sheared grid); resample it first";
    return false;
  }
  g.Normal[0] = axis[0][1] * axis[1][2] - axis[0][2] * axis[1][1];
  g.Normal[1] = axis[0][2] * axis[1][0] - axis[0][0] * axis[1][2];
  g.Normal[2] = axis[0][0] * axis[1][1] - axis[0][1] * axis[1][0];
  g.Reversed = Dot(g.Normal, axis[2]) < 0.0;
  return true;
}

bool CheckWritable(const ImageVolume& volume, const DicomWriteOptions& options, std::string& error) {
  if (volume.Empty()) {
    error = "cannot write an empty volume as DICOM";
    return false;
  }
  vtkDataArray* scalars = volume.Image->GetPointData()->GetScalars();
  if (!scalars || scalars->GetNumberOfComponents() != 1) {
    error = "DICOM writer: only single-component (scalar) volumes are supported";
    return false;
  }
  if (options.Modality != "MR" && options.Modality != "CT") {
    error = "DICOM writer: modality must be CT or MR (got '" + options.Modality + "')";
    return false;
  }
  int dims[3];
  volume.Image->GetDimensions(dims);
  if (dims[0] > 65535 || dims[1] > 65535) {
    error = "DICOM writer: image too large for Rows/Columns";
    return false;
  }
  return true;
}

// What every file of one series shares: UIDs and the creation date and time.
struct SeriesIdentity {
  std::string StudyUID, SeriesUID, FrameUID;
  char Date[16], Time[16];
};

SeriesIdentity NewSeriesIdentity(const DicomWriteOptions& options) {
  SeriesIdentity id;
  id.StudyUID = options.StudyInstanceUID.empty() ? NewUID(SITE_STUDY_UID_ROOT) : options.StudyInstanceUID;
  id.SeriesUID = NewUID(SITE_SERIES_UID_ROOT);
  id.FrameUID = options.FrameOfReferenceUID.empty() ? NewUID(SITE_SERIES_UID_ROOT) : options.FrameOfReferenceUID;
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  std::strftime(id.Date, sizeof id.Date, "%Y%m%d", &tm);
  std::strftime(id.Time, sizeof id.Time, "%H%M%S", &tm);
  return id;
}

// Stores slice k in DICOM's 16-bit pixels; returns the largest round-trip error of the slice.
double QuantizeSlice(vtkDataArray* scalars, const Quantization& q, int k, std::vector<Uint16>& pixels) {
  const size_t sliceSize = pixels.size();
  double maxError = 0.0;
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
  return maxError;
}

// Fills one file's dataset, module by module; the first failing insert stops the rest.
class SliceDataset {
public:
  SliceDataset(DcmDataset* ds, const ImageVolume& volume, const DicomWriteOptions& options,
               const SeriesIdentity& id, const VolumeGrid& g)
      : Ds(ds), Volume(volume), Options(options), Id(id), G(g), MR(options.Modality == "MR") {}

  void PutSOPCommon() {
    Put(DCM_SpecificCharacterSet, "ISO_IR 100");
    Put(DCM_ImageType, "DERIVED\\SECONDARY\\AXIAL");
    Put(DCM_SOPClassUID, MR ? UID_MRImageStorage : UID_CTImageStorage);
    Put(DCM_SOPInstanceUID, NewUID(SITE_INSTANCE_UID_ROOT));
    Put(DCM_ContentDate, Id.Date);
    Put(DCM_ContentTime, Id.Time);
  }
  void PutPatient() {
    Put(DCM_PatientName, Options.PatientName);
    Put(DCM_PatientID, Options.PatientID);
    Put(DCM_PatientBirthDate, "");
    Put(DCM_PatientSex, "O");
  }
  void PutStudy() {
    Put(DCM_StudyDate, Id.Date);
    Put(DCM_StudyTime, Id.Time);
    Put(DCM_AccessionNumber, "");
    Put(DCM_ReferringPhysicianName, "");
    Put(DCM_StudyInstanceUID, Id.StudyUID);
    Put(DCM_StudyID, "1");
  }
  void PutSeries() {
    Put(DCM_SeriesDate, Id.Date);
    Put(DCM_SeriesTime, Id.Time);
    Put(DCM_Modality, MR ? "MR" : "CT");
    Put(DCM_SeriesDescription, Options.SeriesDescription.empty() ? Volume.Description : Options.SeriesDescription);
    Put(DCM_BodyPartExamined, "KNEE");
    Put(DCM_PatientPosition, "FFS");
    Put(DCM_SeriesInstanceUID, Id.SeriesUID);
    Put(DCM_SeriesNumber, std::to_string(Options.SeriesNumber));
  }
  void PutEquipmentAndAcquisition() {
    Put(DCM_Manufacturer, "RoboPlan");
    if (MR) {
      Put(DCM_ScanningSequence, "SE");
      Put(DCM_SequenceVariant, "NONE");
      Put(DCM_ScanOptions, "");
      Put(DCM_MRAcquisitionType, "2D");
      Put(DCM_RepetitionTime, "2500");
      Put(DCM_EchoTime, "30");
      Put(DCM_EchoTrainLength, "1");
      Put(DCM_SpacingBetweenSlices, DS(G.Spacing[2]));
    } else {
      Put(DCM_KVP, "120");
    }
  }
  void PutFrameOfReference() {
    Put(DCM_FrameOfReferenceUID, Id.FrameUID);
    Put(DCM_PositionReferenceIndicator, "");
  }
  void PutImagePlane(int file, int k) {
    double position[3];
    for (int r = 0; r < 3; ++r) position[r] = G.Origin[r] + k * G.Spacing[2] * G.Axis[2][r];
    const auto& axis = G.Axis;
    Put(DCM_SliceThickness, DS(G.Spacing[2]));
    Put(DCM_AcquisitionNumber, "1");
    Put(DCM_InstanceNumber, std::to_string(file + 1));
    Put(DCM_ImagePositionPatient, Join({position[0], position[1], position[2]}));
    Put(DCM_ImageOrientationPatient, Join({axis[0][0], axis[0][1], axis[0][2], axis[1][0], axis[1][1], axis[1][2]}));
    Put(DCM_SliceLocation, DS(Dot(position, G.Normal)));
    Put(DCM_PixelSpacing, Join({G.Spacing[1], G.Spacing[0]}));  // row spacing \ column spacing
  }
  void PutImagePixel(const int dims[3], const Quantization& q, const std::vector<Uint16>& pixels) {
    Put16(DCM_SamplesPerPixel, 1);
    Put(DCM_PhotometricInterpretation, "MONOCHROME2");
    Put16(DCM_Rows, static_cast<Uint16>(dims[1]));
    Put16(DCM_Columns, static_cast<Uint16>(dims[0]));
    Put16(DCM_BitsAllocated, 16);
    Put16(DCM_BitsStored, 16);
    Put16(DCM_HighBit, 15);
    Put16(DCM_PixelRepresentation, q.Signed ? 1 : 0);
    if (Volume.Window > 0.0) {
      Put(DCM_WindowCenter, DS(Volume.Level));
      Put(DCM_WindowWidth, DS(Volume.Window));
    }
    Put(DCM_RescaleIntercept, DS(q.Intercept));
    Put(DCM_RescaleSlope, DS(q.Slope));
    Put(DCM_RescaleType, MR ? "US" : "HU");
    if (Status.good())
      Status = Ds->putAndInsertUint16Array(DCM_PixelData, pixels.data(), static_cast<unsigned long>(pixels.size()));
  }
  OFCondition Status = EC_Normal;

private:
  void Put(const DcmTagKey& tag, const std::string& value) {
    if (Status.good()) Status = Ds->putAndInsertString(tag, value.c_str());
  }
  void Put16(const DcmTagKey& tag, Uint16 value) {
    if (Status.good()) Status = Ds->putAndInsertUint16(tag, value);
  }
  DcmDataset* Ds;
  const ImageVolume& Volume;
  const DicomWriteOptions& Options;
  const SeriesIdentity& Id;
  const VolumeGrid& G;
  const bool MR;
};

}  // namespace

bool WriteDicomSeries(const ImageVolume& volume, const std::string& folder, const DicomWriteOptions& options,
                      std::string& error, DicomWriteResult* result, const ProgressCallback& progress) {
  InitializeDcmtk();
  if (!CheckWritable(volume, options, error)) return false;
  vtkDataArray* scalars = volume.Image->GetPointData()->GetScalars();
  int dims[3];
  volume.Image->GetDimensions(dims);
  VolumeGrid geometry;
  if (!ComputeVolumeGrid(volume, geometry, error)) return false;

  const Quantization q = ChooseQuantization(scalars);
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (!fs::is_directory(folder)) {
    error = "DICOM writer: cannot create folder " + folder + (ec ? ": " + ec.message() : "");
    return false;
  }
  const SeriesIdentity id = NewSeriesIdentity(options);

  std::vector<Uint16> pixels(static_cast<size_t>(dims[0]) * dims[1]);
  double maxError = 0.0;
  for (int file = 0; file < dims[2]; ++file) {
    const int k = geometry.Reversed ? dims[2] - 1 - file : file;
    maxError = std::max(maxError, QuantizeSlice(scalars, q, k, pixels));
    DcmFileFormat format;
    SliceDataset slice(format.getDataset(), volume, options, id, geometry);
    slice.PutSOPCommon();
    slice.PutPatient();
    slice.PutStudy();
    slice.PutSeries();
    slice.PutEquipmentAndAcquisition();
    slice.PutFrameOfReference();
    slice.PutImagePlane(file, k);
    slice.PutImagePixel(dims, q, pixels);
    OFCondition c = slice.Status;
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
    result->SeriesInstanceUID = id.SeriesUID;
    result->StudyInstanceUID = id.StudyUID;
    result->FilesWritten = dims[2];
    result->MaxQuantizationError = maxError;
  }
  return true;
}

}  // namespace rp
