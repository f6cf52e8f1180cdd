#include "rpDicomSegmentation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <new>
#include <stdexcept>

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dctk.h>
#include <dcmtk/dcmfg/fgderimg.h>
#include <dcmtk/dcmfg/fgfracon.h>
#include <dcmtk/dcmfg/fgpixmsr.h>
#include <dcmtk/dcmfg/fgplanor.h>
#include <dcmtk/dcmfg/fgplanpo.h>
#include <dcmtk/dcmfg/fgseg.h>
#include <dcmtk/dcmiod/cielabutil.h>
#include <dcmtk/dcmseg/segdoc.h>
#include <dcmtk/dcmseg/segment.h>
#include <dcmtk/dcmseg/segutils.h>

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>

#include "rpDicomCommon.h"
#include "rpDicomReferenceSeries.h"
#include "rpDicomSegmentCodes.h"
#include "rpImageVolume.h"
#include "rpMemoryBudget.h"
#include "vtkRPSegmentationNode.h"

namespace rp {

namespace {

const DicomSegmentCode& CodeFor(const Segment& segment) {
  return DicomSegmentCodeFor(segment.ID, segment.Name, segment.TissueClass);
}

std::string TissueClassOf(DcmSegment* segment) {
  OFString value;
  segment->getSegmentedPropertyTypeCode().getCodeValue(value);
  return DicomTissueClassOfType(value.c_str());
}

std::string Number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", std::abs(v) < 1e-12 ? 0.0 : v);
  return text;
}

std::string Condition(const OFCondition& c) { return c.text() ? c.text() : "unknown error"; }

bool SameMatrix(const vtkMatrix4x4* a, const vtkMatrix4x4* b, double tolerance) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      if (std::abs(a->GetElement(r, c) - b->GetElement(r, c)) > tolerance) return false;
  return true;
}

// ---------------------------------------------------------------------------------- reading

// One frame of the SEG: where it lies and which segment it belongs to.
struct SegFrame {
  double OriginRAS[3], RowRAS[3], ColumnRAS[3];  // position; unit row and column directions
  double PixelSpacing[2] = {1, 1};               // between rows, between columns
  Uint16 Segment = 0;
  long Slice = 0;  // k on the output grid
};

bool ReadFrameGeometry(DcmSegmentation& seg, std::vector<SegFrame>& frames, double& sliceSpacing, std::string& error) {
  FGInterface& groups = seg.getFunctionalGroups();
  const size_t count = seg.getNumberOfFrames();
  sliceSpacing = 0.0;
  for (size_t f = 0; f < count; ++f) {
    const Uint32 n = static_cast<Uint32>(f);
    auto* position = dynamic_cast<FGPlanePosPatient*>(groups.get(n, DcmFGTypes::EFG_PLANEPOSPATIENT));
    auto* orientation = dynamic_cast<FGPlaneOrientationPatient*>(groups.get(n, DcmFGTypes::EFG_PLANEORIENTPATIENT));
    auto* measures = dynamic_cast<FGPixelMeasures*>(groups.get(n, DcmFGTypes::EFG_PIXELMEASURES));
    auto* segmentation = dynamic_cast<FGSegmentation*>(groups.get(n, DcmFGTypes::EFG_SEGMENTATION));
    SegFrame frame;
    Float64 p[3], o[6];
    if (!position || position->getImagePositionPatient(p[0], p[1], p[2]).bad() || !orientation ||
        orientation->getImageOrientationPatient(o[0], o[1], o[2], o[3], o[4], o[5]).bad() || !measures ||
        measures->getPixelSpacing(frame.PixelSpacing[0], 0).bad() ||
        measures->getPixelSpacing(frame.PixelSpacing[1], 1).bad()) {
      error = "frame " + std::to_string(f + 1) +
              " has no Plane Position, Plane Orientation or Pixel Measures: its geometry is unknown";
      return false;
    }
    if (!segmentation || segmentation->getReferencedSegmentNumber(frame.Segment).bad() || frame.Segment == 0) {
      error = "frame " + std::to_string(f + 1) + " names no segment (Segment Identification Sequence)";
      return false;
    }
    if (f == 0) {
      Float64 spacing = 0.0;
      if (measures->getSpacingBetweenSlices(spacing).good() && spacing > 0) sliceSpacing = spacing;
      else if (measures->getSliceThickness(spacing).good() && spacing > 0) sliceSpacing = -spacing;  // a fallback
    }
    const double lpsToRas[3] = {-1, -1, 1};
    for (int a = 0; a < 3; ++a) {
      frame.OriginRAS[a] = lpsToRas[a] * p[a];
      frame.RowRAS[a] = lpsToRas[a] * o[a];
      frame.ColumnRAS[a] = lpsToRas[a] * o[3 + a];
    }
    frames.push_back(frame);
  }
  if (frames.empty()) {
    error = "no frames";
    return false;
  }
  return true;
}

// The grid the frames span when no referenced series is given: the first frame's plane, slices
// along row x column, spacing from Spacing Between Slices or the smallest gap between frames.
void FrameGrid(const std::vector<SegFrame>& frames, double sliceSpacing, int columns, int rows, vtkMatrix4x4* ijkToRAS,
               int dims[3]) {
  const SegFrame& first = frames.front();
  double normal[3] = {first.RowRAS[1] * first.ColumnRAS[2] - first.RowRAS[2] * first.ColumnRAS[1],
                      first.RowRAS[2] * first.ColumnRAS[0] - first.RowRAS[0] * first.ColumnRAS[2],
                      first.RowRAS[0] * first.ColumnRAS[1] - first.RowRAS[1] * first.ColumnRAS[0]};
  // RAS flips x and y: the cross product of flipped vectors is the flipped LPS normal, as wanted.
  std::vector<double> along;
  for (const SegFrame& f : frames)
    along.push_back(f.OriginRAS[0] * normal[0] + f.OriginRAS[1] * normal[1] + f.OriginRAS[2] * normal[2]);
  std::vector<double> sorted = along;
  std::sort(sorted.begin(), sorted.end());
  double gap = 0.0;
  for (size_t i = 1; i < sorted.size(); ++i)
    if (sorted[i] - sorted[i - 1] > 1e-4 && (gap == 0.0 || sorted[i] - sorted[i - 1] < gap)) gap = sorted[i] - sorted[i - 1];
  double spacing = sliceSpacing > 0 ? sliceSpacing : gap > 0 ? gap : sliceSpacing < 0 ? -sliceSpacing : 1.0;
  const size_t lowest = static_cast<size_t>(std::min_element(along.begin(), along.end()) - along.begin());
  const double shift = sorted.front() - along[lowest];
  ijkToRAS->Identity();
  for (int a = 0; a < 3; ++a) {
    ijkToRAS->SetElement(a, 0, first.RowRAS[a] * first.PixelSpacing[1]);
    ijkToRAS->SetElement(a, 1, first.ColumnRAS[a] * first.PixelSpacing[0]);
    ijkToRAS->SetElement(a, 2, normal[a] * spacing);
    ijkToRAS->SetElement(a, 3, frames[lowest].OriginRAS[a] + shift * normal[a]);
  }
  dims[0] = columns;
  dims[1] = rows;
  dims[2] = static_cast<int>(std::lround((sorted.back() - sorted.front()) / spacing)) + 1;
}

// Every frame must lie on a slice of the grid: its origin at (0, 0, k), its row and column
// steps one voxel along i and j (so orientation and pixel spacing agree too).
bool PlaceFrames(std::vector<SegFrame>& frames, const vtkMatrix4x4* ijkToRAS, const int dims[3], const std::string& grid,
                 std::string& error) {
  vtkNew<vtkMatrix4x4> rasToIJK;
  vtkMatrix4x4::Invert(ijkToRAS, rasToIJK);
  for (size_t f = 0; f < frames.size(); ++f) {
    SegFrame& frame = frames[f];
    double points[3][4] = {{frame.OriginRAS[0], frame.OriginRAS[1], frame.OriginRAS[2], 1}, {0, 0, 0, 1}, {0, 0, 0, 1}};
    for (int a = 0; a < 3; ++a) {
      points[1][a] = frame.OriginRAS[a] + frame.RowRAS[a] * frame.PixelSpacing[1];
      points[2][a] = frame.OriginRAS[a] + frame.ColumnRAS[a] * frame.PixelSpacing[0];
    }
    double ijk[3][4];
    for (int p = 0; p < 3; ++p) rasToIJK->MultiplyPoint(points[p], ijk[p]);
    const long k = std::lround(ijk[0][2]);
    const bool onSlice = std::abs(ijk[0][0]) < 0.01 && std::abs(ijk[0][1]) < 0.01 && std::abs(ijk[0][2] - k) < 0.01 &&
                         k >= 0 && k < dims[2];
    const bool sameAxes = std::abs(ijk[1][0] - 1) < 0.01 && std::abs(ijk[1][1]) < 0.01 && std::abs(ijk[1][2] - k) < 0.01 &&
                          std::abs(ijk[2][0]) < 0.01 && std::abs(ijk[2][1] - 1) < 0.01 && std::abs(ijk[2][2] - k) < 0.01;
    if (!onSlice || !sameAxes) {
      error = "frame " + std::to_string(f + 1) + " (segment " + std::to_string(frame.Segment) + ", position RAS " +
              Number(frame.OriginRAS[0]) + ", " + Number(frame.OriginRAS[1]) + ", " + Number(frame.OriginRAS[2]) +
              ") does not lie on a slice of " + grid +
              (onSlice ? " (its orientation or pixel spacing differs)" : " (it falls at voxel " + Number(ijk[0][0]) +
                                                                              ", " + Number(ijk[0][1]) + ", " +
                                                                              Number(ijk[0][2]) + ")");
      return false;
    }
    frame.Slice = k;
  }
  return true;
}

// The frames' pixels into a labelmap (label = segment number; a voxel in two segments goes to
// the higher number, counted per pair).
bool FillLabelmap(DcmSegmentation& seg, const std::vector<SegFrame>& frames, int columns, int rows, vtkImageData* labels,
                  Uint16 fractionalThreshold, std::vector<std::string>* warnings, std::string& error) {
  const bool binary = seg.getSegmentationType() == DcmSegTypes::ST_BINARY;
  const size_t sliceSize = static_cast<size_t>(columns) * rows;
  vtkDataArray* scalars = labels->GetPointData()->GetScalars();
  scalars->Fill(0);
  std::map<std::pair<int, int>, size_t> overlaps;
  for (size_t f = 0; f < frames.size(); ++f) {
    const DcmIODTypes::Frame* frame = seg.getFrame(f);
    std::unique_ptr<DcmIODTypes::Frame> unpacked;
    if (frame && binary) {
      unpacked.reset(DcmSegUtils::unpackBinaryFrame(frame, static_cast<Uint16>(rows), static_cast<Uint16>(columns)));
      frame = unpacked.get();
    }
    if (!frame || !frame->pixData || frame->length < sliceSize) {
      error = "frame " + std::to_string(f + 1) + " has fewer than " + std::to_string(sliceSize) + " pixels (truncated?)";
      return false;
    }
    const vtkIdType base = static_cast<vtkIdType>(frames[f].Slice * sliceSize);
    const int segment = frames[f].Segment;
    for (size_t i = 0; i < sliceSize; ++i) {
      const Uint8 value = frame->pixData[i];
      if (binary ? value == 0 : value < fractionalThreshold) continue;
      const int existing = static_cast<int>(scalars->GetComponent(base + static_cast<vtkIdType>(i), 0));
      if (existing != 0 && existing != segment) ++overlaps[{std::min(existing, segment), std::max(existing, segment)}];
      scalars->SetComponent(base + static_cast<vtkIdType>(i), 0, std::max(existing, segment));
    }
  }
  if (warnings)
    for (const auto& [pair, count] : overlaps)
      warnings->push_back(std::to_string(count) + " voxel(s) belong to segments " + std::to_string(pair.first) +
                          " and " + std::to_string(pair.second) + ": a labelmap holds one, segment " +
                          std::to_string(pair.second) + " kept");
  return true;
}

void ReadSegments(DcmSegmentation& seg, vtkRPSegmentationNode* node) {
  node->RemoveAllSegments();
  for (size_t n = 1; n <= seg.getNumberOfSegments(); ++n) {
    DcmSegment* s = seg.getSegment(n);
    if (!s) continue;
    Segment segment;
    OFString label, description;
    s->getSegmentLabel(label);
    s->getSegmentDescription(description);
    segment.LabelValue = static_cast<int>(n);
    segment.Name = label.empty() ? "Segment " + std::to_string(n) : label.c_str();
    segment.ID = !description.empty() ? description.c_str() : segment.Name;
    if (node->GetSegmentByID(segment.ID)) segment.ID += "_" + std::to_string(n);
    Uint16 L = 0, a = 0, b = 0;
    if (s->getRecommendedDisplayCIELabValue(L, a, b).good())
      IODCIELabUtil::dicomLab2RGB(segment.Color[0], segment.Color[1], segment.Color[2], L, a, b);
    segment.TissueClass = TissueClassOf(s);
    node->SetSegment(segment);
  }
}

}  // namespace

// `given`: the referenced series already read; else `referencePath` (when not empty) is read.
static bool ReadSegmentation(const std::string& path, vtkRPSegmentationNode* node, std::string& error,
                             const std::string& referencePath, const DicomReferenceSeries* given,
                             std::vector<std::string>* warnings) {
  InitializeDcmtk();
  std::string file;
  const int kind = DicomSegmentationObjectKind(path, &file, &error);
  if (kind < 0) return false;
  if (kind != 1) {
    error = path + (kind == 2 ? " is an RTSTRUCT, not a DICOM SEG" : " is not (and holds no) DICOM Segmentation object (SEG)");
    return false;
  }
  const std::string what = "DICOM SEG " + file + ": ";
  DcmFileFormat format;
  OFCondition status = format.loadFile(file.c_str());
  DcmSegmentation* loaded = nullptr;
  if (status.good()) status = DcmSegmentation::loadDataset(*format.getDataset(), loaded);
  std::unique_ptr<DcmSegmentation> seg(loaded);
  if (status.bad() || !seg) {
    error = what + "cannot be read (" + Condition(status) + ")";
    return false;
  }
  DcmDataset* ds = format.getDataset();
  Uint16 rows = 0, columns = 0, maxFractional = 255;
  ds->findAndGetUint16(DCM_Rows, rows);
  ds->findAndGetUint16(DCM_Columns, columns);
  ds->findAndGetUint16(DCM_MaximumFractionalValue, maxFractional);
  std::vector<SegFrame> frames;
  double sliceSpacing = 0.0;
  if (rows == 0 || columns == 0 || !ReadFrameGeometry(*seg, frames, sliceSpacing, error)) {
    error = what + (rows == 0 || columns == 0 ? std::string("no Rows/Columns") : error);
    return false;
  }
  vtkNew<vtkMatrix4x4> ijkToRAS;
  int dims[3];
  std::string grid = "the grid its frames span";
  if (given || !referencePath.empty()) {
    DicomReferenceSeries read;
    if (!given && !ReadDicomReferenceSeries(referencePath, read, error)) {
      error = what + "referenced series: " + error;
      return false;
    }
    const DicomReferenceSeries& reference = given ? *given : read;
    OFString frameOfReference;
    ds->findAndGetOFString(DCM_FrameOfReferenceUID, frameOfReference);
    if (!frameOfReference.empty() && !reference.FrameOfReferenceUID.empty() &&
        reference.FrameOfReferenceUID != frameOfReference.c_str()) {
      error = what + "its Frame of Reference (" + frameOfReference.c_str() + ") is not the referenced series' (" +
              reference.FrameOfReferenceUID + ")";
      return false;
    }
    ijkToRAS->DeepCopy(reference.Volume.IJKToRAS);
    reference.Volume.Image->GetDimensions(dims);
    grid = "the referenced series " + reference.SeriesInstanceUID;
    if (dims[0] != columns || dims[1] != rows) {
      error = what + "frames of " + std::to_string(columns) + "x" + std::to_string(rows) + " pixels, the referenced series' images " +
              std::to_string(dims[0]) + "x" + std::to_string(dims[1]);
      return false;
    }
  } else {
    FrameGrid(frames, sliceSpacing, columns, rows, ijkToRAS, dims);
  }
  if (!PlaceFrames(frames, ijkToRAS, dims, grid, error)) {
    error = what + error;
    return false;
  }
  const size_t segments = seg->getNumberOfSegments();
  const int64_t size[3] = {dims[0], dims[1], dims[2]};
  if (!CheckImageFitsInMemory(size, segments <= 255 ? 1.0 : 2.0, what + "labelmap", error)) return false;
  auto labels = vtkSmartPointer<vtkImageData>::New();
  labels->SetDimensions(dims);
  labels->AllocateScalars(segments <= 255 ? VTK_UNSIGNED_CHAR : VTK_UNSIGNED_SHORT, 1);
  const bool fractional = seg->getSegmentationType() == DcmSegTypes::ST_FRACTIONAL;
  const Uint16 threshold = static_cast<Uint16>((maxFractional + 1) / 2);
  if (fractional && warnings)
    warnings->push_back("fractional SEG: voxels at or above half the Maximum Fractional Value (" +
                        std::to_string(threshold) + " of " + std::to_string(maxFractional) + ") taken as inside");
  if (!FillLabelmap(*seg, frames, columns, rows, labels, std::max<Uint16>(threshold, 1), warnings, error)) {
    error = what + error;
    return false;
  }
  ImageVolume volume;
  volume.Image = labels;
  volume.IJKToRAS->DeepCopy(ijkToRAS);
  const int previous = node->StartModify();
  CopyToNode(volume, node);
  ReadSegments(*seg, node);
  OFString description;
  if (ds->findAndGetOFString(DCM_SeriesDescription, description).good() && !description.empty())
    node->SetName(description.c_str());
  node->EndModify(previous);
  return true;
}

// ---------------------------------------------------------------------------------- writing

namespace {

bool AddSegments(DcmSegmentation& seg, vtkRPSegmentationNode* node, std::vector<std::pair<Uint16, int>>& numbers,
                 std::string& error) {
  for (const Segment& segment : node->GetSegments()) {
    const DicomSegmentCode& code = CodeFor(segment);
    DcmSegment* s = nullptr;
    OFCondition c = DcmSegment::create(s, segment.Name.empty() ? segment.ID.c_str() : segment.Name.c_str(),
                                       CodeSequenceMacro(code.CategoryValue, "SCT", code.CategoryMeaning),
                                       CodeSequenceMacro(code.TypeValue, "SCT", code.TypeMeaning),
                                       DcmSegTypes::SAT_SEMIAUTOMATIC, "RoboPlan");
    if (c.bad() || !s) {
      error = "segment '" + segment.ID + "': " + Condition(c);
      return false;
    }
    s->setSegmentDescription(segment.ID.c_str(), OFFalse);
    double L = 0, a = 0, b = 0;
    IODCIELabUtil::rgb2DicomLab(L, a, b, segment.Color[0], segment.Color[1], segment.Color[2]);
    s->setRecommendedDisplayCIELabValue(static_cast<Uint16>(std::lround(L)), static_cast<Uint16>(std::lround(a)),
                                        static_cast<Uint16>(std::lround(b)));
    Uint16 number = 0;
    c = seg.addSegment(s, number);
    if (c.bad()) {
      delete s;
      error = "segment '" + segment.ID + "': " + Condition(c);
      return false;
    }
    numbers.emplace_back(number, segment.LabelValue);
  }
  return true;
}

// One binary frame per segment and slice that holds it, with its position, dimension indices
// and source image.
bool AddFrames(DcmSegmentation& seg, vtkRPSegmentationNode* node, const DicomReferenceSeries& reference,
               const std::vector<std::pair<Uint16, int>>& numbers, size_t& added, std::string& error) {
  vtkImageData* image = node->GetImageData();
  int dims[3];
  image->GetDimensions(dims);
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  const size_t sliceSize = static_cast<size_t>(dims[0]) * dims[1];
  std::vector<Uint8> pixels(sliceSize);
  vtkMatrix4x4* ijkToRAS = node->GetIJKToRASMatrix();
  added = 0;
  for (const auto& [number, labelValue] : numbers) {
    for (int k = 0; k < dims[2]; ++k) {
      bool any = false;
      for (size_t i = 0; i < sliceSize; ++i) {
        pixels[i] = scalars->GetComponent(static_cast<vtkIdType>(k * sliceSize + i), 0) == labelValue ? 1 : 0;
        any = any || pixels[i];
      }
      if (!any) continue;
      const double ijk[4] = {0, 0, double(k), 1};
      double ras[4];
      ijkToRAS->MultiplyPoint(ijk, ras);
      std::unique_ptr<FGPlanePosPatient> position(
          FGPlanePosPatient::createMinimal(Number(-ras[0]).c_str(), Number(-ras[1]).c_str(), Number(ras[2]).c_str()));
      FGFrameContent content;
      content.setDimensionIndexValues(number, 0);
      content.setDimensionIndexValues(static_cast<Uint32>(k + 1), 1);
      OFVector<FGBase*> groups;
      groups.push_back(position.get());
      groups.push_back(&content);
      std::unique_ptr<FGDerivationImage> derivation;
      if (!reference.SOPInstanceUIDs[k].empty()) {
        ImageSOPInstanceReferenceMacro source;
        source.setReferencedSOPClassUID(reference.SOPClassUIDs[k].c_str());
        source.setReferencedSOPInstanceUID(reference.SOPInstanceUIDs[k].c_str());
        OFVector<ImageSOPInstanceReferenceMacro> sources;
        sources.push_back(source);
        derivation.reset(DcmSegmentation::createDerivationImageFG(sources, "Segmentation of the referenced image"));
        if (derivation) groups.push_back(derivation.get());
      }
      const OFCondition c = seg.addFrame(pixels.data(), number, groups);
      if (c.bad()) {
        error = "frame of segment " + std::to_string(number) + " on slice " + std::to_string(k) + ": " + Condition(c);
        return false;
      }
      ++added;
    }
  }
  return true;
}

// The Common Instance Reference module's Referenced Series Sequence: every image of the series.
void AddReferencedSeries(DcmDataset* ds, const DicomReferenceSeries& reference) {
  DcmItem* series = nullptr;
  if (ds->findOrCreateSequenceItem(DCM_ReferencedSeriesSequence, series, 0).bad() || !series) return;
  series->putAndInsertString(DCM_SeriesInstanceUID, reference.SeriesInstanceUID.c_str());
  for (size_t k = 0; k < reference.SOPInstanceUIDs.size(); ++k) {
    if (reference.SOPInstanceUIDs[k].empty()) continue;
    DcmItem* instance = nullptr;
    if (series->findOrCreateSequenceItem(DCM_ReferencedInstanceSequence, instance, -2).good() && instance) {
      instance->putAndInsertString(DCM_ReferencedSOPClassUID, reference.SOPClassUIDs[k].c_str());
      instance->putAndInsertString(DCM_ReferencedSOPInstanceUID, reference.SOPInstanceUIDs[k].c_str());
    }
  }
}

// Strings padded with NULs instead of spaces (some writers do; the knee CT's patient and study
// attributes) violate their VR for dcmiod's checks: trimmed before they are imported.
void CleanStrings(DcmItem* item) {
  for (unsigned long i = 0; i < item->card(); ++i) {
    DcmElement* element = item->getElement(i);
    if (!element || !element->isaString() || element->getLengthField() == 0) continue;
    OFString value;
    if (element->getOFStringArray(value).bad()) continue;
    size_t length = value.length();
    while (length > 0 && (value[length - 1] == ' ' || value[length - 1] == '\0')) --length;
    if (length != value.length()) element->putOFStringArray(value.substr(0, length));
  }
}

std::unique_ptr<DcmSegmentation> CreateSegmentation(vtkRPSegmentationNode* node, const DicomReferenceSeries& reference,
                                                    const DicomSegmentationWriteOptions& options, std::string& error) {
  int dims[3];
  node->GetImageData()->GetDimensions(dims);
  DcmSegmentation* created = nullptr;
  IODGeneralEquipmentModule::EquipmentInfo equipment("RoboPlan", "RoboPlan", "1", "1.0");
  ContentIdentificationMacro content("1", options.ContentLabel.c_str(), options.SeriesDescription.c_str(), "RoboPlan");
  OFCondition c = DcmSegmentation::createBinarySegmentation(created, static_cast<Uint16>(dims[1]),
                                                            static_cast<Uint16>(dims[0]), equipment, content);
  std::unique_ptr<DcmSegmentation> seg(created);
  DcmFileFormat source;
  if (c.good() && seg)
    c = source.loadFileUntilTag(reference.FirstFile.c_str(), EXS_Unknown, EGL_noChange, DCM_MaxReadLength,
                                ERM_autoDetect, DCM_PixelData);
  if (c.good()) {
    CleanStrings(source.getDataset());
    c = seg->importFromSourceImage(*source.getDataset());
  }
  if (c.good()) c = seg->getSeries().setSeriesNumber(options.SeriesNumber.c_str());
  if (c.good()) c = seg->getSeries().setSeriesDescription(options.SeriesDescription.c_str());
  if (c.bad() || !seg) {
    error = "cannot create the SEG (" + Condition(c) + ")";
    return nullptr;
  }
  const vtkMatrix4x4* m = reference.Volume.IJKToRAS;
  double spacing[3];
  reference.Volume.GetSpacing(spacing);
  FGPixelMeasures measures;
  measures.setPixelSpacing((Number(spacing[1]) + "\\" + Number(spacing[0])).c_str());
  measures.setSliceThickness(Number(spacing[2]).c_str());
  measures.setSpacingBetweenSlices(Number(spacing[2]).c_str());
  std::string o[6];
  for (int a = 0; a < 3; ++a) {
    const double flip = a < 2 ? -1.0 : 1.0;  // RAS → LPS
    o[a] = Number(flip * m->GetElement(a, 0) / spacing[0]);
    o[3 + a] = Number(flip * m->GetElement(a, 1) / spacing[1]);
  }
  std::unique_ptr<FGPlaneOrientationPatient> orientation(FGPlaneOrientationPatient::createMinimal(
      o[0].c_str(), o[1].c_str(), o[2].c_str(), o[3].c_str(), o[4].c_str(), o[5].c_str()));
  c = seg->addForAllFrames(measures);
  if (c.good() && orientation) c = seg->addForAllFrames(*orientation);
  char uid[100];
  dcmGenerateUniqueIdentifier(uid, SITE_INSTANCE_UID_ROOT);
  IODMultiframeDimensionModule& dimensions = seg->getDimensions();
  if (c.good())
    c = dimensions.addDimensionIndex(DCM_ReferencedSegmentNumber, uid, DCM_SegmentIdentificationSequence,
                                     "ReferencedSegmentNumber");
  if (c.good())
    c = dimensions.addDimensionIndex(DCM_ImagePositionPatient, uid, DCM_PlanePositionSequence, "ImagePositionPatient");
  if (c.bad()) {
    error = "cannot set the SEG's shared geometry (" + Condition(c) + ")";
    return nullptr;
  }
  return seg;
}

}  // namespace

static bool WriteSegmentation(vtkRPSegmentationNode* node, const std::string& referencePath, const std::string& outputFile,
                            std::string& error, const DicomSegmentationWriteOptions& options) {
  InitializeDcmtk();
  if (!node || !node->GetImageData() || !node->GetImageData()->GetPointData()->GetScalars()) {
    error = "no segmentation to write";
    return false;
  }
  if (node->GetNumberOfSegments() == 0) {
    error = "the segmentation has no segments";
    return false;
  }
  DicomReferenceSeries reference;
  if (!ReadDicomReferenceSeries(referencePath, reference, error)) {
    error = "referenced series: " + error;
    return false;
  }
  int dims[3], referenceDims[3];
  node->GetImageData()->GetDimensions(dims);
  reference.Volume.Image->GetDimensions(referenceDims);
  if (!std::equal(dims, dims + 3, referenceDims) || !SameMatrix(node->GetIJKToRASMatrix(), reference.Volume.IJKToRAS, 1e-3)) {
    error = "the segmentation's grid (" + std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" +
            std::to_string(dims[2]) + ") is not the referenced series' grid (" + std::to_string(referenceDims[0]) + "x" +
            std::to_string(referenceDims[1]) + "x" + std::to_string(referenceDims[2]) +
            (std::equal(dims, dims + 3, referenceDims) ? ", other origin, spacing or directions" : "") +
            "): a SEG's frames lie on the referenced images; resample the segmentation onto the series first";
    return false;
  }
  std::unique_ptr<DcmSegmentation> seg = CreateSegmentation(node, reference, options, error);
  std::vector<std::pair<Uint16, int>> numbers;
  size_t frames = 0;
  if (!seg || !AddSegments(*seg, node, numbers, error) || !AddFrames(*seg, node, reference, numbers, frames, error))
    return false;
  if (frames == 0) {
    error = "every segment is empty: nothing to write";
    return false;
  }
  DcmFileFormat format;
  OFCondition c = seg->writeDataset(*format.getDataset());
  if (c.bad()) {
    error = "cannot encode the SEG (" + Condition(c) + ")";
    return false;
  }
  AddReferencedSeries(format.getDataset(), reference);
  c = format.saveFile(outputFile.c_str(), EXS_LittleEndianExplicit);
  if (c.bad()) {
    error = "cannot write " + outputFile + " (" + Condition(c) + ")";
    return false;
  }
  return true;
}

bool ReadDicomSegmentation(const std::string& path, vtkRPSegmentationNode* node, std::string& error,
                           const std::string& referencePath, std::vector<std::string>* warnings) {
  return Guarded("reading", path, error,
                 [&] { return ReadSegmentation(path, node, error, referencePath, nullptr, warnings); });
}

bool ReadDicomSegmentation(const std::string& file, vtkRPSegmentationNode* node, std::string& error,
                           const DicomReferenceSeries& reference, std::vector<std::string>* warnings) {
  return Guarded("reading", file, error,
                 [&] { return ReadSegmentation(file, node, error, "", &reference, warnings); });
}

bool WriteDicomSegmentation(vtkRPSegmentationNode* node, const std::string& referencePath, const std::string& outputFile,
                            std::string& error, const DicomSegmentationWriteOptions& options) {
  return Guarded("writing", outputFile, error,
                 [&] { return WriteSegmentation(node, referencePath, outputFile, error, options); });
}

}  // namespace rp
