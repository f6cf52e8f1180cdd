#pragma once
// The main job's report: a self-contained HTML page (report.html) with the run's stages, every
// figure beside its target (pass/fail/not scored), and the pictures (PNG files in the same
// folder: screenshots, force plots, timing histograms, speed-against-accuracy charts).
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace rp {

class Report {
 public:
  enum class Verdict { Pass, Fail, NotScored };

  struct Figure {
    std::string Stage;     // e.g. "CT↔MR registration"
    std::string Name;      // e.g. "RMS error at the bone surface"
    double Value = 0;
    std::string Unit;      // e.g. "mm"
    std::string Target;    // human text, e.g. "< 1 mm"
    Verdict Result = Verdict::NotScored;
    std::string Note;      // why not scored, or detail
  };
  struct Picture {
    std::string Stage, File, Caption;  // File relative to the report folder
  };
  struct StageRecord {
    std::string Name;
    double Seconds = 0;
    bool Ok = true;
    std::string Message;
  };

  explicit Report(std::string title) : Title(std::move(title)) {}

  /// A figure checked against a target: value < maximum (or > minimum) passes.
  void AddFigureBelow(const std::string& stage, const std::string& name, double value, const std::string& unit,
                      double maximum, const std::string& note = "");
  void AddFigureAbove(const std::string& stage, const std::string& name, double value, const std::string& unit,
                      double minimum, const std::string& note = "");
  /// A figure with no target, or one that cannot be scored (e.g. no ground truth).
  void AddFigure(const std::string& stage, const std::string& name, double value, const std::string& unit,
                 const std::string& note = "");
  void AddNotScored(const std::string& stage, const std::string& name, const std::string& why);
  void AddPicture(const std::string& stage, const std::string& file, const std::string& caption);
  /// A picture that could not be drawn: a named warning at the top of the report (and under
  /// "picturesMissing" in the JSON) saying which picture is missing and why; the run goes on.
  void AddMissingPicture(const std::string& stage, const std::string& file, const std::string& why);
  /// AddPicture when `drawn`, else AddMissingPicture with `why`. Returns `drawn`.
  bool AddPictureIf(bool drawn, const std::string& stage, const std::string& file, const std::string& caption,
                    const std::string& why);
  void AddStage(const StageRecord& stage) { this->Stages.push_back(stage); }
  void AddNote(const std::string& text) { this->Notes.push_back(text); }
  /// A top-level entry of report.json beside the figures, for scripts (e.g. "executions": the
  /// plan's executions, "plans": each plan's figures as `roboplan plan --json` prints them).
  /// `json` is JSON text; set again, it replaces the entry.
  void SetJsonSection(const std::string& key, const std::string& json) { this->Sections[key] = json; }

  const std::vector<Figure>& GetFigures() const { return this->Figures; }
  const std::vector<StageRecord>& GetStages() const { return this->Stages; }
  int CountFailed() const;

  std::string ToHtml() const;
  /// The stages and figures as JSON (for scripts and tests): {"title", "stages": [...],
  /// "figures": [{"stage", "name", "value" (null when not measured), "unit", "target", "result"
  /// ("pass" | "fail" | "not scored"), "note"}], "pictures": [{"stage", "file"}],
  /// "picturesMissing": [{"stage", "file", "why"}], and each SetJsonSection entry}.
  std::string ToJson() const;
  /// Writes the HTML report atomically, and the JSON beside it (same name, .json). Returns false
  /// with `error`.
  bool Write(const std::string& path, std::string& error) const;

 private:
  std::string Title;
  std::vector<Figure> Figures;
  std::vector<Picture> Pictures;
  std::vector<Picture> MissingPictures;  // Caption holds why
  std::vector<StageRecord> Stages;
  std::vector<std::string> Notes;
  std::map<std::string, std::string> Sections;
};

}  // namespace rp
