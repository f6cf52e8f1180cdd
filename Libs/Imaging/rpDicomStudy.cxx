#include "rpDicomStudy.h"

#include <algorithm>
#include <filesystem>

#include "rpDicomCommon.h"
#include "rpDicomReferenceSeries.h"
#include "rpDicomRtStruct.h"
#include "rpDicomSegmentation.h"
#include "vtkRPSegmentationNode.h"

namespace rp {

namespace {

std::string FileName(const std::string& path) { return std::filesystem::path(path).filename().string(); }

std::string ObjectName(const DicomSegmentationObjectInfo& object) {
  return object.Kind + " " + FileName(object.File);
}

// Reads the image stacks of the study, each once: those asked for (`keep`) become its volumes,
// the others are read only as the grid a segmentation lies on.
class StudyReader {
 public:
  StudyReader(const std::string& path, const DicomScanResult& scan, const DicomStudyOptions& options,
              const ProgressCallback& progress)
      : Path(path), Scan(scan), Options(options), Progress(progress) {}

  // Every loadable stack (a series of several stacks needs --series: left out with its choices).
  void ReadAllStacks(DicomStudy& study, std::vector<std::string>& problems) {
    std::vector<std::string> multiStack;
    for (const DicomSeriesInfo& series : this->Scan.Series) {
      if (series.StackCount > 1) {
        if (std::find(multiStack.begin(), multiStack.end(), series.SeriesInstanceUID) != multiStack.end()) continue;
        multiStack.push_back(series.SeriesInstanceUID);
        std::string choices;
        ChooseDicomStack(this->Scan, this->Path, series.SeriesInstanceUID, choices);
        problems.push_back(choices);
        continue;
      }
      std::string error;
      if (!this->ReadStack(series, study, true, error)) problems.push_back(error);
    }
  }

  // The stack read as a volume of the study (`keep`), or only for a segmentation's grid.
  bool ReadStack(const DicomSeriesInfo& series, DicomStudy& study, bool keep, std::string& error) {
    DicomStudyVolume read;
    read.Series = series;
    if (!ReadDicomSeries(series, read.Volume, error, this->Options.Dicom, &study.Warnings, this->Progress)) return false;
    (keep ? study.Volumes : this->GridsOnly).push_back(std::move(read));
    return true;
  }

  // The series `object` lies on, read (or nullptr): the one it names, else the only one read in
  // its Frame of Reference, else (RTSTRUCT) the only one read. `index`: in study.Volumes, or -1.
  const DicomStudyVolume* ReferenceOf(const DicomSegmentationObjectInfo& object, DicomStudy& study, int& index) {
    index = -1;
    if (!object.ReferencedSeriesUID.empty()) {
      for (size_t v = 0; v < study.Volumes.size(); ++v)
        if (study.Volumes[v].Series.SeriesInstanceUID == object.ReferencedSeriesUID) return &study.Volumes[index = int(v)];
      for (const DicomStudyVolume& grid : this->GridsOnly)
        if (grid.Series.SeriesInstanceUID == object.ReferencedSeriesUID) return &grid;
      // Named but not read yet (one object asked for): read it for its grid only.
      std::string error;
      if (const DicomSeriesInfo* series = ChooseDicomStack(this->Scan, this->Path, object.ReferencedSeriesUID, error))
        if (this->ReadStack(*series, study, false, error)) return &this->GridsOnly.back();
    }
    std::vector<int> sameFrame;
    for (size_t v = 0; v < study.Volumes.size(); ++v)
      if (!object.FrameOfReferenceUID.empty() && study.Volumes[v].Series.FrameOfReferenceUID == object.FrameOfReferenceUID)
        sameFrame.push_back(int(v));
    if (sameFrame.size() == 1) return &study.Volumes[index = sameFrame.front()];
    if (object.Kind == "RTSTRUCT" && study.Volumes.size() == 1) return &study.Volumes[index = 0];
    return nullptr;
  }

  // One SEG or RTSTRUCT, on the series it references. False (and `error`) when it is left out.
  bool ReadObject(const DicomSegmentationObjectInfo& object, DicomStudy& study, std::string& error) {
    DicomStudySegmentation read;
    read.Object = object;
    read.Node = vtkSmartPointer<vtkRPSegmentationNode>::New();
    const DicomStudyVolume* on = this->ReferenceOf(object, study, read.ReferencedVolume);
    std::vector<std::string> notes;
    bool ok = false;
    if (object.Kind == "RTSTRUCT") {
      if (!on) {
        error = ObjectName(object) + ": the image series its contours were drawn on (" +
                (object.ReferencedSeriesUID.empty() ? "not named" : object.ReferencedSeriesUID) + ") is not in " +
                this->Path + "; left out";
        return false;
      }
      ok = ReadDicomRtStruct(object.File, read.Node, error, DicomReferenceFromVolume(on->Series, on->Volume), &notes);
    } else if (on) {
      ok = ReadDicomSegmentation(object.File, read.Node, error, DicomReferenceFromVolume(on->Series, on->Volume), &notes);
      if (!ok) {
        notes.push_back("not on the grid of series " + on->Series.StackID + " (" + error +
                        "): read on the grid its frames span");
        read.ReferencedVolume = -1;
      }
    }
    if (object.Kind == "SEG" && !ok) {
      if (!on && !object.ReferencedSeriesUID.empty())
        notes.push_back("its series " + object.ReferencedSeriesUID + " is not in " + this->Path +
                        ": read on the grid its frames span");
      ok = ReadDicomSegmentation(object.File, read.Node, error, "", &notes);
    }
    for (const std::string& note : notes) study.Warnings.push_back(ObjectName(object) + ": " + note);
    if (!ok) return false;
    if (read.Node->GetName().empty()) read.Node->SetName(std::filesystem::path(object.File).stem().string());
    study.Segmentations.push_back(std::move(read));
    return true;
  }

 private:
  const std::string& Path;
  const DicomScanResult& Scan;
  const DicomStudyOptions& Options;
  const ProgressCallback& Progress;
  std::vector<DicomStudyVolume> GridsOnly;  // series read only as a segmentation's grid
};

// Notes on what the scan skipped, as ReadDicomVolume gives them.
void AddScanWarnings(const DicomScanResult& scan, std::vector<std::string>& warnings) {
  if (scan.NonDicomFiles > 0) warnings.push_back(std::to_string(scan.NonDicomFiles) + " non-DICOM file(s) skipped");
  for (const auto& c : scan.CorruptFiles) warnings.push_back("skipped " + c);
}

// One image stack, as ReadDicomVolume reads it (its messages unchanged).
bool ReadOneStack(const std::string& path, const DicomScanResult& scan, const DicomStudyOptions& options,
                  DicomStudy& study, std::string& error, const ProgressCallback& progress) {
  const DicomSeriesInfo* chosen = ChooseDicomStack(scan, path, options.Series, error);
  if (!chosen) return false;
  AddScanWarnings(scan, study.Warnings);
  DicomStudyVolume read;
  read.Series = *chosen;
  if (!ReadDicomSeries(*chosen, read.Volume, error, options.Dicom, &study.Warnings, progress)) {
    if (!scan.CorruptFiles.empty() && chosen->CorruptFiles.empty())
      error += " (also skipped as corrupt or truncated: " + scan.CorruptFiles.front() + ")";
    return false;
  }
  study.Volumes.push_back(std::move(read));
  return true;
}

bool ReadStudy(const std::string& path, DicomStudy& study, std::string& error, const DicomStudyOptions& options,
               const ProgressCallback& progress) {
  DicomScanResult scan;
  if (!ScanDicom(path, scan, error, progress)) return false;
  const auto named = std::find_if(scan.Segmentations.begin(), scan.Segmentations.end(),
                                  [&](const DicomSegmentationObjectInfo& o) { return o.SeriesInstanceUID == options.Series; });
  StudyReader reader(path, scan, options, progress);
  if (!options.Series.empty() && named != scan.Segmentations.end()) return reader.ReadObject(*named, study, error);
  // One image stack asked for, or all the folder holds: read as ReadDicomVolume reads it.
  std::string single;
  if (!options.Series.empty() || (scan.Segmentations.empty() && ChooseDicomStack(scan, path, "", single)))
    return ReadOneStack(path, scan, options, study, error, progress);
  std::vector<std::string> problems;
  reader.ReadAllStacks(study, problems);
  for (const DicomSegmentationObjectInfo& object : scan.Segmentations) {
    std::string problem;
    if (!reader.ReadObject(object, study, problem)) problems.push_back(problem);
  }
  if (study.Volumes.empty() && study.Segmentations.empty()) {
    if (problems.empty()) ChooseDicomStack(scan, path, "", error);  // names what the folder holds
    else if (problems.size() == 1) error = problems.front();
    else error = "nothing in " + path + " could be read: " + problems.front() + "; " +
                 std::to_string(problems.size() - 1) + " more (roboplan dicom lists them)";
    return false;
  }
  AddScanWarnings(scan, study.Warnings);
  for (const std::string& problem : problems) study.Warnings.push_back("left out: " + problem);
  return true;
}

}  // namespace

bool ReadDicomStudy(const std::string& path, DicomStudy& study, std::string& error, const DicomStudyOptions& options,
                    const ProgressCallback& progress) {
  return Guarded("reading", path, error, [&] {
    DicomStudy read;
    if (!ReadStudy(path, read, error, options, progress)) return false;
    study = std::move(read);
    return true;
  });
}

}  // namespace rp
