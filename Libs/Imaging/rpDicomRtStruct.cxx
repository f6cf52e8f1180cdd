#include "rpDicomRtStruct.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <new>
#include <stdexcept>
#include <sstream>

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dctk.h>
#include <dcmtk/dcmrt/drtstrct.h>

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>

#include "rpDicomCommon.h"
#include "rpDicomReferenceSeries.h"
#include "rpImageVolume.h"
#include "rpMemoryBudget.h"
#include "vtkRPSegmentationNode.h"

namespace fs = std::filesystem;

namespace rp {

namespace {

struct Roi {
  int Number = 0;
  std::string Name;
  double Color[3] = {1, 1, 0};
  bool HasColor = false;
  std::vector<std::vector<double>> Contours;  // CLOSED_PLANAR: x, y, z (LPS mm) per point
  int NotRegions = 0;                         // POINT / OPEN_PLANAR contours left out
};

std::string Fmt(double v) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(1);
  s << v;
  return s.str();
}

// dcmrt's sequences step once past their last item (onto an empty, invalid one): stop there.
template <typename Sequence>
bool Valid(const OFCondition& step, Sequence& sequence) {
  return step.good() && sequence.getCurrentItem().isValid();
}

// The referenced series' UID, from Referenced Frame of Reference > RT Referenced Study > RT
// Referenced Series ("" when absent).
std::string ReferencedSeriesUID(DRTStructureSetIOD& rt) {
  OFString uid;
  auto& frames = rt.getReferencedFrameOfReferenceSequence();
  for (OFCondition c = frames.gotoFirstItem(); Valid(c, frames); c = frames.gotoNextItem()) {
    auto& studies = frames.getCurrentItem().getRTReferencedStudySequence();
    for (OFCondition s = studies.gotoFirstItem(); Valid(s, studies); s = studies.gotoNextItem()) {
      auto& series = studies.getCurrentItem().getRTReferencedSeriesSequence();
      if (Valid(series.gotoFirstItem(), series) && series.getCurrentItem().getSeriesInstanceUID(uid).good()) return uid.c_str();
    }
  }
  return "";
}

std::vector<Roi> ReadRois(DRTStructureSetIOD& rt) {
  std::vector<Roi> rois;
  auto& structures = rt.getStructureSetROISequence();
  for (OFCondition c = structures.gotoFirstItem(); Valid(c, structures); c = structures.gotoNextItem()) {
    Roi roi;
    OFString name;
    Sint32 number = 0;
    structures.getCurrentItem().getROINumber(number);
    structures.getCurrentItem().getROIName(name);
    roi.Number = number;
    roi.Name = name.empty() ? "ROI " + std::to_string(number) : name.c_str();
    rois.push_back(roi);
  }
  auto& contours = rt.getROIContourSequence();
  for (OFCondition c = contours.gotoFirstItem(); Valid(c, contours); c = contours.gotoNextItem()) {
    auto& item = contours.getCurrentItem();
    Sint32 number = 0;
    item.getReferencedROINumber(number);
    auto roi = std::find_if(rois.begin(), rois.end(), [&](const Roi& r) { return r.Number == number; });
    if (roi == rois.end()) {
      rois.push_back(Roi());
      roi = rois.end() - 1;
      roi->Number = number;
      roi->Name = "ROI " + std::to_string(number);
    }
    Sint32 rgb[3];
    roi->HasColor = true;
    for (unsigned long a = 0; a < 3; ++a) {
      roi->HasColor = roi->HasColor && item.getROIDisplayColor(rgb[a], a).good();
      if (roi->HasColor) roi->Color[a] = std::clamp(rgb[a], 0, 255) / 255.0;
    }
    auto& sequence = item.getContourSequence();
    for (OFCondition s = sequence.gotoFirstItem(); Valid(s, sequence); s = sequence.gotoNextItem()) {
      OFString type;
      sequence.getCurrentItem().getContourGeometricType(type);
      OFVector<Float64> data;
      sequence.getCurrentItem().getContourData(data);
      if (type != "CLOSED_PLANAR" || data.size() < 9) {
        ++roi->NotRegions;
        continue;
      }
      roi->Contours.emplace_back(data.begin(), data.end() - static_cast<long>(data.size() % 3));
    }
  }
  return rois;
}

// XORs the inside of one closed polygon (continuous i, j) into a slice mask: a voxel centre is
// inside when a ray along +i crosses the polygon an odd number of times.
void XorPolygon(const std::vector<double>& i, const std::vector<double>& j, int columns, int rows, std::vector<char>& mask) {
  const size_t n = i.size();
  std::vector<double> crossings;
  const double jMin = *std::min_element(j.begin(), j.end()), jMax = *std::max_element(j.begin(), j.end());
  for (int row = std::max(0, int(std::ceil(jMin))); row <= std::min(rows - 1, int(std::floor(jMax))); ++row) {
    crossings.clear();
    for (size_t a = 0; a < n; ++a) {
      const size_t b = (a + 1) % n;
      if ((j[a] <= row) == (j[b] <= row)) continue;  // half-open: each vertex counted once
      crossings.push_back(i[a] + (row - j[a]) * (i[b] - i[a]) / (j[b] - j[a]));
    }
    std::sort(crossings.begin(), crossings.end());
    for (size_t c = 0; c + 1 < crossings.size(); c += 2) {
      const int from = std::max(0, int(std::ceil(crossings[c])));
      const int to = std::min(columns - 1, int(std::ceil(crossings[c + 1])) - 1);
      for (int col = from; col <= to; ++col) mask[static_cast<size_t>(row) * columns + col] ^= 1;
    }
  }
}

// Rasterizes one ROI into `inside` (per voxel); counts the contours that lie on no slice.
void RasterizeRoi(const Roi& roi, vtkMatrix4x4* rasToIJK, const int dims[3], std::vector<char>& inside,
                  std::vector<double>& offSlice) {
  const size_t sliceSize = static_cast<size_t>(dims[0]) * dims[1];
  std::map<long, std::vector<char>> slices;
  for (const std::vector<double>& contour : roi.Contours) {
    const size_t n = contour.size() / 3;
    std::vector<double> i(n), j(n);
    double kSum = 0.0, kMin = 1e300, kMax = -1e300;
    for (size_t p = 0; p < n; ++p) {
      const double ras[4] = {-contour[3 * p], -contour[3 * p + 1], contour[3 * p + 2], 1.0};
      double ijk[4];
      rasToIJK->MultiplyPoint(ras, ijk);
      i[p] = ijk[0];
      j[p] = ijk[1];
      kSum += ijk[2];
      kMin = std::min(kMin, ijk[2]);
      kMax = std::max(kMax, ijk[2]);
    }
    const double k = kSum / double(n);
    const long slice = std::lround(k);
    if (slice < 0 || slice >= dims[2] || std::abs(k - double(slice)) > 0.1 || kMax - kMin > 0.2) {
      offSlice.push_back(contour[2]);
      continue;
    }
    std::vector<char>& mask = slices[slice];
    if (mask.empty()) mask.assign(sliceSize, 0);
    XorPolygon(i, j, dims[0], dims[1], mask);
  }
  for (const auto& [slice, mask] : slices)
    for (size_t v = 0; v < sliceSize; ++v)
      if (mask[v]) inside[static_cast<size_t>(slice) * sliceSize + v] = 1;
}

std::string FindRtStruct(const std::string& path, std::string& error) {
  std::string file;
  const int kind = DicomSegmentationObjectKind(path, &file, &error);
  if (kind == 2) return file;
  if (kind >= 0) error = path + (kind == 1 ? " is a DICOM SEG, not an RTSTRUCT" : " is not (and holds no) RTSTRUCT");
  return "";
}

}  // namespace

// `given`: the series the contours were drawn on, already read; else it is read from
// `referencePath`, or found in the RTSTRUCT's folder.
static bool ReadRtStruct(const std::string& path, vtkRPSegmentationNode* node, std::string& error,
                         const std::string& referencePath, const DicomReferenceSeries* given,
                         std::vector<std::string>* warnings) {
  InitializeDcmtk();
  const std::string file = FindRtStruct(path, error);
  if (file.empty()) return false;
  const std::string what = "RTSTRUCT " + file + ": ";
  DcmFileFormat format;
  DRTStructureSetIOD rt;
  OFCondition status = format.loadFile(file.c_str());
  if (status.good()) status = rt.read(*format.getDataset());
  if (status.bad()) {
    error = what + "cannot be read (" + status.text() + ")";
    return false;
  }
  const std::string seriesUID = ReferencedSeriesUID(rt);
  const std::string folder = !referencePath.empty() ? referencePath
                             : fs::is_directory(path)  ? path
                                                       : fs::path(file).parent_path().string();
  DicomReferenceSeries read;
  if (!given && !ReadDicomReferenceSeries(folder, read, error, referencePath.empty() ? seriesUID : "") &&
      !ReadDicomReferenceSeries(folder, read, error)) {
    error = what + "the image series its contours were drawn on (" + (seriesUID.empty() ? "not named" : seriesUID) +
            "): " + error + " (give it as the reference series)";
    return false;
  }
  const DicomReferenceSeries& reference = given ? *given : read;
  int dims[3];
  reference.Volume.Image->GetDimensions(dims);
  vtkNew<vtkMatrix4x4> rasToIJK;
  vtkMatrix4x4::Invert(reference.Volume.IJKToRAS, rasToIJK);
  const int64_t size[3] = {dims[0], dims[1], dims[2]};
  if (!CheckImageFitsInMemory(size, 3.0, what + "labelmap", error)) return false;  // labels + one ROI's mask
  const std::vector<Roi> rois = ReadRois(rt);
  if (rois.empty()) {
    error = what + "no ROI (Structure Set ROI Sequence is empty)";
    return false;
  }
  auto labels = vtkSmartPointer<vtkImageData>::New();
  labels->SetDimensions(dims);
  labels->AllocateScalars(rois.size() <= 255 ? VTK_UNSIGNED_CHAR : VTK_UNSIGNED_SHORT, 1);
  vtkDataArray* scalars = labels->GetPointData()->GetScalars();
  scalars->Fill(0);
  const int previous = node->StartModify();
  node->RemoveAllSegments();
  const size_t total = static_cast<size_t>(dims[0]) * dims[1] * dims[2];
  std::vector<char> inside;
  std::map<std::pair<int, int>, size_t> overlaps;
  for (size_t r = 0; r < rois.size(); ++r) {
    const Roi& roi = rois[r];
    const int label = static_cast<int>(r) + 1;
    inside.assign(total, 0);
    std::vector<double> offSlice;
    RasterizeRoi(roi, rasToIJK, dims, inside, offSlice);
    for (size_t v = 0; v < total; ++v) {
      if (!inside[v]) continue;
      const int existing = static_cast<int>(scalars->GetComponent(static_cast<vtkIdType>(v), 0));
      if (existing) ++overlaps[{existing, label}];
      scalars->SetComponent(static_cast<vtkIdType>(v), 0, label);
    }
    if (warnings && !offSlice.empty())
      warnings->push_back("ROI '" + roi.Name + "': " + std::to_string(offSlice.size()) +
                          " contour(s) on no slice of the image grid (first at z = " + Fmt(offSlice.front()) +
                          " mm LPS): left out");
    if (warnings && roi.NotRegions)
      warnings->push_back("ROI '" + roi.Name + "': " + std::to_string(roi.NotRegions) +
                          " POINT/OPEN_PLANAR contour(s) (not regions) left out");
    Segment segment;
    segment.ID = roi.Name;
    segment.Name = roi.Name;
    segment.LabelValue = label;
    std::copy(roi.Color, roi.Color + 3, segment.Color);
    node->SetSegment(segment);
  }
  if (warnings)
    for (const auto& [pair, count] : overlaps)
      warnings->push_back(std::to_string(count) + " voxel(s) inside ROIs '" + rois[pair.first - 1].Name + "' and '" +
                          rois[pair.second - 1].Name + "': a labelmap holds one, '" + rois[pair.second - 1].Name +
                          "' kept");
  ImageVolume volume;
  volume.Image = labels;
  volume.IJKToRAS->DeepCopy(reference.Volume.IJKToRAS);
  CopyToNode(volume, node);
  OFString label;
  if (rt.getStructureSetLabel(label).good() && !label.empty()) node->SetName(label.c_str());
  node->EndModify(previous);
  return true;
}

bool ReadDicomRtStruct(const std::string& path, vtkRPSegmentationNode* node, std::string& error,
                       const std::string& referencePath, std::vector<std::string>* warnings) {
  return Guarded("reading", path, error,
                 [&] { return ReadRtStruct(path, node, error, referencePath, nullptr, warnings); });
}

bool ReadDicomRtStruct(const std::string& file, vtkRPSegmentationNode* node, std::string& error,
                       const DicomReferenceSeries& reference, std::vector<std::string>* warnings) {
  return Guarded("reading", file, error,
                 [&] { return ReadRtStruct(file, node, error, "", &reference, warnings); });
}

}  // namespace rp
