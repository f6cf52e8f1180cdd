#pragma once
// The study of issue 42's tests, as a PACS would deliver it: the real knee CT
// (../shared/data/knee-ct-vhf) in one folder with a DICOM SEG of its bone labels and an RTSTRUCT
// of the same labels. The SEG is made the way a user makes one, with two `roboplan convert`
// commands: labels.nrrd → knee.seg.nrrd (names and colours from a Slicer colour table), then
// knee.seg.nrrd → DICOM SEG on the CT; the RTSTRUCT is written by pydicom from the labels'
// contours, as rpDicomSegmentationTest writes one. Tests that use it link RoboPlanVolumesLogic
// and skip without pydicom (rpDicomPython.h).
#include <array>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rpDicomPython.h"
#include "rpImageVolume.h"
#include "rpSharedData.h"
#include "rpVolumeFiles.h"
#include "rpVolumesCommands.h"

namespace rp::testing {

/// The bones of knee-ct-vhf/labels.nrrd (label value = index + 1) as the colour table names and
/// colours them: colours far from grey and from the views' red, yellow and green crosshairs.
struct KneeLabel {
  const char* Name;
  std::array<int, 3> Color;  // 0..255
};
inline const std::array<KneeLabel, 3>& KneeLabels() {
  static const std::array<KneeLabel, 3> labels = {{{"Tibia", {230, 150, 20}}, {"Fibula", {40, 110, 240}},
                                                   {"Patella", {200, 40, 200}}}};
  return labels;
}

struct KneeStudy {
  std::filesystem::path Folder;     // CT + SEG + RTSTRUCT
  std::filesystem::path CtFolder;   // the CT alone
  std::filesystem::path Labels;     // labels.nrrd (shared data)
  std::filesystem::path Table;      // the Slicer colour table (.ctbl)
  std::filesystem::path SegNrrd;    // labels.nrrd as a segmentation (first command)
  std::filesystem::path Seg;        // Folder/knee-bones-seg.dcm (second command)
  std::filesystem::path RtStruct;   // Folder/knee-bones-rtstruct.dcm (pydicom)
};

/// Makes the study under `dir`; false with `error` naming the step that failed.
inline bool MakeKneeStudy(const std::filesystem::path& dir, KneeStudy& study, std::string& error) {
  namespace fs = std::filesystem;
  fs::remove_all(dir);
  study.CtFolder = dir / "ct";
  study.Folder = dir / "study";
  study.Labels = rptest::SharedDataPath("knee-ct-vhf/labels.nrrd");
  study.Table = dir / "knee-bones.ctbl";
  study.SegNrrd = dir / "knee-bones.seg.nrrd";
  study.Seg = study.Folder / "knee-bones-seg.dcm";
  study.RtStruct = study.Folder / "knee-bones-rtstruct.dcm";
  fs::create_directories(dir);
  fs::copy(rptest::SharedDataPath("knee-ct-vhf/dicom"), study.CtFolder, fs::copy_options::recursive);
  fs::copy(study.CtFolder, study.Folder, fs::copy_options::recursive);
  {  // 3D Slicer's colour table format (vtkMRMLColorTableStorageNode): value name r g b a
    std::ofstream table(study.Table);
    table << "# Color table file knee-bones.ctbl\n# 4 values\n0 Background 0 0 0 0\n";
    for (size_t l = 0; l < KneeLabels().size(); ++l) {
      const auto& c = KneeLabels()[l].Color;
      table << l + 1 << " " << KneeLabels()[l].Name << " " << c[0] << " " << c[1] << " " << c[2] << " 255\n";
    }
  }
  std::ostringstream out, err;
  if (RunConvertCommand({study.Labels.string(), study.SegNrrd.string(), "--labels", study.Table.string()}, out, err) != 0 ||
      RunConvertCommand({study.SegNrrd.string(), study.Seg.string(), "--reference", study.CtFolder.string()}, out, err) != 0) {
    error = "roboplan convert: " + err.str();
    return false;
  }
  // The RTSTRUCT: each label's contours per slice, written by pydicom against the CT's images.
  ImageVolume labels;
  if (!ReadVolume(study.Labels.string(), labels, error)) return false;
  int dims[3];
  labels.Image->GetDimensions(dims);
  nlohmann::json spec = {{"rois", nlohmann::json::array()}};
  for (size_t l = 0; l < KneeLabels().size(); ++l) {
    nlohmann::json roi = {{"name", KneeLabels()[l].Name}, {"color", KneeLabels()[l].Color},
                          {"contours", nlohmann::json::array()}};
    for (int k = 0; k < dims[2]; ++k)
      for (const auto& contour : SliceContours(labels.Image, labels.IJKToRAS, static_cast<int>(l) + 1, k))
        roi["contours"].push_back(contour);
    spec["rois"].push_back(roi);
  }
  std::ofstream(dir / "contours.json") << spec.dump();
  if (RunPython(RtStructScript, dir, {(dir / "contours.json").string(), study.CtFolder.string(), study.RtStruct.string()}) != 0) {
    error = "pydicom could not write the RTSTRUCT: " + Slurp(dir / "python.log");
    return false;
  }
  return true;
}

}  // namespace rp::testing
