#pragma once
// pydicom as the independent reader (and RTSTRUCT writer) of the DICOM tests: run a script with
// Debian's python3 (python3-pydicom, python3-numpy; tests skip without them), and the scripts the
// DICOM segmentation, study and Volumes tests share. Also the contours of a labelmap's slices
// (vtkMarchingSquares), from which the RTSTRUCT script writes a structure set.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <vtkCellArray.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkMarchingSquares.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkStripper.h>

namespace rp::testing {

inline const char* const Python = "/usr/bin/python3";

inline bool HavePydicom() { return std::system("/usr/bin/python3 -c 'import pydicom, numpy' >/dev/null 2>&1") == 0; }

/// Runs `script` with `arguments`; its stdout goes to scratch/python.out, stderr to python.log.
inline int RunPython(const std::string& script, const std::filesystem::path& scratch,
                     const std::vector<std::string>& arguments) {
  const std::filesystem::path file = scratch / "script.py";
  std::ofstream(file) << script;
  std::string command = std::string(Python) + " '" + file.string() + "'";
  for (const auto& a : arguments) command += " '" + a + "'";
  command += " >'" + (scratch / "python.out").string() + "' 2>'" + (scratch / "python.log").string() + "'";
  return std::system(command.c_str());
}

inline std::string Slurp(const std::filesystem::path& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// pydicom as an independent reader of our SEG: prints what a PACS or viewer would see.
inline const char* const CheckSegScript = R"PY(
import json, sys
import numpy as np
import pydicom
ds = pydicom.dcmread(sys.argv[1])
frames = ds.pixel_array.reshape(int(ds.NumberOfFrames), ds.Rows, ds.Columns)
out = {"sopClass": ds.SOPClassUID, "modality": ds.Modality, "type": ds.SegmentationType,
       "bitsAllocated": ds.BitsAllocated, "frames": int(ds.NumberOfFrames),
       "referencedSeries": ds.ReferencedSeriesSequence[0].SeriesInstanceUID,
       "referencedInstances": len(ds.ReferencedSeriesSequence[0].ReferencedInstanceSequence),
       "frameOfReference": ds.FrameOfReferenceUID, "studyUID": ds.StudyInstanceUID,
       "segments": [{"number": s.SegmentNumber, "label": s.SegmentLabel,
                     "type": s.SegmentedPropertyTypeCodeSequence[0].CodeMeaning,
                     "lab": [int(v) for v in s.RecommendedDisplayCIELabValue]} for s in ds.SegmentSequence],
       "voxels": {}, "z": {}, "derivedFrom": 0}
for f, item in enumerate(ds.PerFrameFunctionalGroupsSequence):
    n = str(item.SegmentIdentificationSequence[0].ReferencedSegmentNumber)
    out["voxels"][n] = out["voxels"].get(n, 0) + int(frames[f].sum())
    out["z"].setdefault(n, []).append(float(item.PlanePositionSequence[0].ImagePositionPatient[2]))
    if "DerivationImageSequence" in item:
        out["derivedFrom"] += 1
print(json.dumps(out))
)PY";

// pydicom rewrites a file in Deflated Explicit VR Little Endian and prints its transfer syntax
// and SOP class as it reads them back.
inline const char* const DeflateScript = R"PY(
import json, sys
import pydicom
from pydicom.uid import DeflatedExplicitVRLittleEndian
ds = pydicom.dcmread(sys.argv[1])
ds.file_meta.TransferSyntaxUID = DeflatedExplicitVRLittleEndian
ds.is_little_endian = True
ds.is_implicit_VR = False
ds.save_as(sys.argv[2], write_like_original=False)
back = pydicom.dcmread(sys.argv[2])
print(json.dumps({"syntax": str(back.file_meta.TransferSyntaxUID), "sopClass": str(back.SOPClassUID)}))
)PY";

// pydicom rewrites our binary SEG as a fractional (8-bit, probability) one: inside 200 of 255,
// plus a faint 100 halo one row above each inside pixel (below the 128 threshold).
inline const char* const FractionalScript = R"PY(
import sys
import numpy as np
import pydicom
ds = pydicom.dcmread(sys.argv[1])
frames = ds.pixel_array.reshape(int(ds.NumberOfFrames), ds.Rows, ds.Columns).astype(np.uint8)
halo = np.zeros_like(frames)
halo[:, :-1, :] = frames[:, 1:, :]
out = np.where(frames > 0, 200, np.where(halo > 0, 100, 0)).astype(np.uint8)
ds.SegmentationType = "FRACTIONAL"
ds.SegmentationFractionalType = "PROBABILITY"
ds.MaximumFractionalValue = 255
ds.BitsAllocated = 8
ds.BitsStored = 8
ds.HighBit = 7
ds.PixelData = out.tobytes()
ds.save_as(sys.argv[2])
)PY";

// pydicom writes an RTSTRUCT from contours (JSON: ROIs with names, colours, LPS points) that
// reference the CT's images.
inline const char* const RtStructScript = R"PY(
import json, sys, glob
import pydicom
from pydicom.dataset import Dataset, FileDataset, FileMetaDataset
from pydicom.sequence import Sequence
from pydicom.uid import generate_uid, ExplicitVRLittleEndian
spec = json.load(open(sys.argv[1]))
ct = [pydicom.dcmread(f, stop_before_pixels=True) for f in sorted(glob.glob(sys.argv[2] + "/*.dcm"))]
meta = FileMetaDataset()
meta.MediaStorageSOPClassUID = "1.2.840.10008.5.1.4.1.1.481.3"
meta.MediaStorageSOPInstanceUID = generate_uid()
meta.TransferSyntaxUID = ExplicitVRLittleEndian
ds = FileDataset(sys.argv[3], {}, file_meta=meta, preamble=b"\0" * 128)
ds.SOPClassUID = meta.MediaStorageSOPClassUID
ds.SOPInstanceUID = meta.MediaStorageSOPInstanceUID
ds.Modality = "RTSTRUCT"
for key in ("PatientName", "PatientID", "StudyInstanceUID", "StudyDate", "StudyID"):
    if key in ct[0]:
        setattr(ds, key, getattr(ct[0], key))
ds.SeriesInstanceUID = generate_uid()
ds.StructureSetLabel = "knee bones"
series = Dataset(); series.SeriesInstanceUID = ct[0].SeriesInstanceUID
series.ContourImageSequence = Sequence([Dataset() for _ in ct])
for item, image in zip(series.ContourImageSequence, ct):
    item.ReferencedSOPClassUID = image.SOPClassUID; item.ReferencedSOPInstanceUID = image.SOPInstanceUID
study = Dataset(); study.ReferencedSOPClassUID = "1.2.840.10008.3.1.2.3.1"
study.ReferencedSOPInstanceUID = ct[0].StudyInstanceUID; study.RTReferencedSeriesSequence = Sequence([series])
frame = Dataset(); frame.FrameOfReferenceUID = ct[0].get("FrameOfReferenceUID", generate_uid())
frame.RTReferencedStudySequence = Sequence([study])
ds.ReferencedFrameOfReferenceSequence = Sequence([frame])
ds.StructureSetROISequence = Sequence(); ds.ROIContourSequence = Sequence()
for number, roi in enumerate(spec["rois"], start=1):
    s = Dataset(); s.ROINumber = number; s.ROIName = roi["name"]
    s.ReferencedFrameOfReferenceUID = frame.FrameOfReferenceUID; s.ROIGenerationAlgorithm = "AUTOMATIC"
    ds.StructureSetROISequence.append(s)
    c = Dataset(); c.ReferencedROINumber = number; c.ROIDisplayColor = roi["color"]; c.ContourSequence = Sequence()
    for points in roi["contours"]:
        item = Dataset(); item.ContourGeometricType = "CLOSED_PLANAR"
        item.NumberOfContourPoints = len(points) // 3
        item.ContourData = ["%.4f" % v for v in points]
        c.ContourSequence.append(item)
    ds.ROIContourSequence.append(c)
ds.is_little_endian = True; ds.is_implicit_VR = False
ds.save_as(sys.argv[3], write_like_original=False)
)PY";


// Closed contours (LPS mm) of one label on one slice, at the 0.5 iso-line between voxel
// centres (vtkMarchingSquares on the slice padded by one background voxel).
inline std::vector<std::vector<double>> SliceContours(vtkImageData* labels, vtkMatrix4x4* ijkToRAS, int label, int k) {
  int dims[3];
  labels->GetDimensions(dims);
  vtkNew<vtkImageData> slice;
  slice->SetDimensions(dims[0] + 2, dims[1] + 2, 1);
  slice->SetOrigin(-1, -1, k);
  slice->AllocateScalars(VTK_FLOAT, 1);
  float* out = static_cast<float*>(slice->GetScalarPointer());
  bool any = false;
  for (int j = -1; j <= dims[1]; ++j)
    for (int i = -1; i <= dims[0]; ++i) {
      const bool inside = i >= 0 && j >= 0 && i < dims[0] && j < dims[1] &&
                          labels->GetScalarComponentAsDouble(i, j, k, 0) == label;
      out[(j + 1) * (dims[0] + 2) + (i + 1)] = inside ? 1.0f : 0.0f;
      any = any || inside;
    }
  std::vector<std::vector<double>> contours;
  if (!any) return contours;
  vtkNew<vtkMarchingSquares> squares;
  squares->SetInputData(slice);
  squares->SetValue(0, 0.5);
  vtkNew<vtkStripper> stripper;
  stripper->SetInputConnection(squares->GetOutputPort());
  stripper->JoinContiguousSegmentsOn();
  stripper->Update();
  vtkPolyData* lines = stripper->GetOutput();
  vtkNew<vtkIdList> ids;
  for (lines->GetLines()->InitTraversal(); lines->GetLines()->GetNextCell(ids);) {
    std::vector<double> points;
    vtkIdType n = ids->GetNumberOfIds();
    if (n > 1 && ids->GetId(0) == ids->GetId(n - 1)) --n;  // closed: the first point repeated
    for (vtkIdType p = 0; p < n; ++p) {
      double ijk[4] = {0, 0, 0, 1}, ras[4];
      lines->GetPoint(ids->GetId(p), ijk);
      ijk[3] = 1;
      ijkToRAS->MultiplyPoint(ijk, ras);
      points.insert(points.end(), {-ras[0], -ras[1], ras[2]});
    }
    if (points.size() >= 9) contours.push_back(points);
  }
  return contours;
}

}  // namespace rp::testing
