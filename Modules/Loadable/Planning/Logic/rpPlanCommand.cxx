#include "rpPlanCommand.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>

#include <nlohmann/json.hpp>
#include <vtkNew.h>

#include "rpArgParser.h"
#include "rpDataLoader.h"
#include "rpPlanPictures.h"
#include "rpPlanReport.h"
#include "rpSceneFormats.h"
#include "rpSegmentationIO.h"
#include "vtkRPCutPlaneNode.h"
#include "vtkRPModelNode.h"
#include "vtkRPPlanningLogic.h"
#include "vtkRPScalarVolumeNode.h"
#include "vtkRPScene.h"
#include "vtkRPScrewNode.h"
#include "vtkRPSegmentationNode.h"
#include "vtkRPTrajectoryNode.h"
#include "rpStrings.h"

namespace rp {
namespace {

// The scene a sub-command works in, with what it loaded.
struct PlanSession {
  vtkNew<vtkRPScene> Scene;
  vtkNew<vtkRPPlanningLogic> Logic;
  vtkRPScalarVolumeNode* CT = nullptr;
  vtkRPSegmentationNode* Segmentation = nullptr;
  PlanSession() { this->Logic->SetScene(this->Scene); }
};

int Fail(std::ostream& err, const std::string& command, const std::string& message) {
  err << "roboplan plan " << command << ": " << message << "\n";
  return 1;
}

// The options every sub-command that reads the patient shares.
void DeclarePatient(ArgParser& parser, bool volumeRequired) {
  parser.Option("volume", "CT", "the CT: any volume the loader opens (NRRD, NIfTI, MetaImage, a DICOM folder or file)")
      .Input(FileKind::Image);
  if (volumeRequired) parser.Required();
  parser.Option("segmentation", "seg", "segmentation (.seg.nrrd) or labelmap volume: where bone is, per segment")
      .Input(FileKind::LabelMap);
  parser.Option("bone", "segment", "a segment that is bone (ID, name or label value; default: bone tissue classes, "
                                   "or every segment of a labelmap without them)")
      .Repeatable();
  parser.Option("protect", "file[:mm]",
                "a structure at risk with its safety margin: a model file, a segmentation/labelmap file (every segment), "
                "or a segment of --segmentation; margin in mm after ':' (default 0)")
      .Repeatable();
  parser.Option("materials", "json", "tissue material table (default Resources/Materials/materials.json)").Input(FileKind::Any, {".json"});
}

bool LoadVolume(PlanSession& s, const std::string& path, std::string& error) {
  LoadResult result;
  vtkRPNode* node = LoadSingleNode(s.Scene, path, result);
  s.CT = vtkRPScalarVolumeNode::SafeDownCast(node);
  if (!s.CT) error = node ? "'" + path + "' is not a volume" : result.Error;
  return s.CT != nullptr;
}

vtkRPSegmentationNode* LoadSegmentation(PlanSession& s, const std::string& path, std::string& error) {
  vtkNew<vtkRPSegmentationNode> node;
  if (!ReadSegmentationOrLabelmap(path, node, error)) return nullptr;
  node->SetName(std::filesystem::path(path).filename().string());
  return vtkRPSegmentationNode::SafeDownCast(s.Scene->AddNode(node));
}

// "<file or segment>[:<mm>]": a trailing ":<number>" is the margin.
void SplitMargin(const std::string& text, std::string& what, double& margin, bool& hasMargin) {
  what = text, margin = 0, hasMargin = false;
  const size_t colon = text.rfind(':');
  if (colon == std::string::npos) return;
  char* end = nullptr;
  const std::string tail = text.substr(colon + 1);
  const double value = std::strtod(tail.c_str(), &end);
  if (tail.empty() || *end != '\0') return;
  what = text.substr(0, colon), margin = value, hasMargin = true;
}

bool AddProtected(PlanSession& s, const std::string& argument, std::string& error) {
  std::string what;
  double margin;
  bool hasMargin;
  SplitMargin(argument, what, margin, hasMargin);
  if (hasMargin && !(margin >= 0 && std::isfinite(margin))) {
    error = "--protect " + argument + ": the safety margin must be a number of mm >= 0";
    return false;
  }
  const StructureProtection protection{true, margin};
  if (!std::filesystem::exists(what)) {  // a segment of the segmentation
    const Segment* found = s.Segmentation ? s.Segmentation->FindSegment(what) : nullptr;
    if (!found) {
      error = "--protect " + argument + ": no such file" + (s.Segmentation ? " and no such segment in the segmentation" : "");
      return false;
    }
    Segment segment = *found;
    segment.Protection = protection;
    s.Segmentation->SetSegment(segment);
    return true;
  }
  // A model file, or a segmentation (or labelmap) whose every segment is the structure.
  LoadResult result;
  vtkRPNode* node = LoadSingleNode(s.Scene, what, result);
  if (auto* model = vtkRPModelNode::SafeDownCast(node)) {
    model->SetProtection(protection);
    return true;
  }
  if (node) s.Scene->RemoveNode(node);
  vtkRPSegmentationNode* segmentation = LoadSegmentation(s, what, error);
  if (!segmentation) {
    error = "--protect " + argument + ": " + (result.Ok ? error : result.Error);
    return false;
  }
  for (Segment segment : segmentation->GetSegments()) {
    segment.Protection = protection;
    segmentation->SetSegment(segment);
  }
  return true;
}

// Loads --volume, --segmentation, --protect, --materials and sets the logic's patient data.
bool LoadPatient(const ArgParser& parser, PlanSession& s, std::string& error) {
  if (parser.Has("materials")) {
    MaterialTable materials;
    if (!LoadMaterialTable(materials, error, parser.Get("materials"))) return false;
    s.Logic->SetMaterials(materials);
  }
  if (parser.Has("volume") && !LoadVolume(s, parser.Get("volume"), error)) return false;
  if (parser.Has("segmentation") && !(s.Segmentation = LoadSegmentation(s, parser.Get("segmentation"), error))) return false;
  for (const std::string& p : parser.GetAll("protect"))
    if (!AddProtected(s, p, error)) return false;
  return s.Logic->SetPatientData(s.CT, s.Segmentation, error, parser.GetAll("bone"));
}

// --out: a .mrk.json holds the one plan node; a scene file everything (CT, segmentation,
// structures, plans, models).
bool WriteOut(PlanSession& s, vtkRPNode* node, const std::string& path, std::string& error) {
  if (HasExtension(path, ".mrk.json")) return SaveDataFile(node, path, error);
  if (!IsSceneFileName(path)) {
    error = "--out " + path + ": write a plan as .mrk.json, or a scene as .rpscene, .mrml or .mrb";
    return false;
  }
  SceneTransferReport report;
  if (WriteSceneFile(s.Scene, path, report) && report.FirstProblem().empty()) return true;
  error = report.FirstProblem().empty() ? report.Error : report.FirstProblem();
  return false;
}

}  // namespace

// ---------------------------------------------------------------- trajectory and screw
namespace {

ArgParser TrajectoryParser(bool screw) {
  ArgParser parser(screw ? "plan screw" : "plan trajectory",
                   screw ? "Plan a screw (a trajectory with the screw's diameter, length and head; tip at the target) and "
                           "measure it against the CT: length and length per tissue, HU profile, cortical share of its "
                           "surface, breach (Gertzbein-Robbins grade), clearance from each structure at risk."
                         : "Plan a trajectory (a Slicer markups line, entry to target, with the tool's diameter) and "
                           "measure it against the CT: length and length per tissue, HU profile along the axis and over "
                           "the tool's cross-section, cortical breach, clearance from each structure at risk.");
  DeclarePatient(parser, true);
  parser.Option("entry", "R,A,S", "entry point (RAS, mm)").Point();
  parser.Option("target", "R,A,S", "target point (RAS, mm)").Point();
  parser.Option("plan", "plan.mrk.json", "an existing plan (a markups line) instead of --entry/--target")
      .Input(FileKind::Points, {".mrk.json"});
  parser.Option("diameter", "mm", "tool (drill) diameter").Number().GreaterThan(0);
  parser.Option("name", "text", "the plan's name", screw ? "Screw" : "Trajectory");
  parser.Option("tissue", "class", "the tissue the tool is meant to go through (materials.json)", "bone");
  if (screw) {
    parser.Option("screw-diameter", "mm", "screw (outer thread) diameter", "6.5").Number().GreaterThan(0);
    parser.Option("screw-length", "mm", "screw length, from its tip at the target back", "40").Number().GreaterThan(0);
    parser.Option("head-diameter", "mm", "head diameter", "10").Number().GreaterThan(0);
    parser.Option("head-length", "mm", "head length (0: headless)", "5").Number().AtLeast(0);
  }
  parser.Option("out", "file", "write the plan: .mrk.json (a Slicer markups line), or a scene (.rpscene, .mrml, .mrb)")
      .Output(FileKind::Points, {".mrk.json", ".rpscene", ".mrml", ".mrb"});
  parser.Option("profile-chart", "png", "chart of the HU profile (axis, cross-section) with the bone ranges")
      .Output(FileKind::Any, {".png"});
  return parser;
}

// The plan node from --plan, or from --entry/--target/--diameter.
vtkRPTrajectoryNode* MakeTrajectory(const ArgParser& parser, PlanSession& s, bool screw, std::string& error) {
  if (parser.Has("plan") == (parser.Has("entry") || parser.Has("target"))) {
    error = "give --entry and --target (with --diameter), or --plan";
    return nullptr;
  }
  vtkRPTrajectoryNode* node = nullptr;
  if (parser.Has("plan")) {
    LoadResult result;
    node = vtkRPTrajectoryNode::SafeDownCast(LoadSingleNode(s.Scene, parser.Get("plan"), result));
    if (!node) error = result.Ok ? "'" + parser.Get("plan") + "' holds no trajectory (a markups line)" : result.Error;
    if (!node || !screw || node->IsA("vtkRPScrewNode")) return node;
    error = "'" + parser.Get("plan") + "' is a trajectory, not a screw: use `roboplan plan trajectory`";
    return nullptr;
  }
  if (!parser.Has("entry") || !parser.Has("target") || !parser.Has("diameter")) {
    error = "--entry, --target and --diameter are needed (or --plan)";
    return nullptr;
  }
  vtkSmartPointer<vtkRPTrajectoryNode> created =
      screw ? vtkSmartPointer<vtkRPTrajectoryNode>::Take(vtkRPScrewNode::New()) : vtkSmartPointer<vtkRPTrajectoryNode>::New();
  created->SetName(parser.Get("name"));
  const auto entry = parser.GetDoubles("entry", 3), target = parser.GetDoubles("target", 3);
  created->SetEntryAndTarget(entry.data(), target.data());
  created->SetToolDiameterMm(parser.GetDouble("diameter"));
  created->SetIntendedTissue(parser.Get("tissue"));
  created->SetPlannedOn(vtkRPPlanningLogic::VolumeIdentity(s.CT));
  if (auto* sc = vtkRPScrewNode::SafeDownCast(created)) {
    sc->SetScrewDiameterMm(parser.GetDouble("screw-diameter"));
    sc->SetScrewLengthMm(parser.GetDouble("screw-length"));
    sc->SetHeadDiameterMm(parser.GetDouble("head-diameter"));
    sc->SetHeadLengthMm(parser.GetDouble("head-length"));
  }
  return vtkRPTrajectoryNode::SafeDownCast(s.Scene->AddNode(created));
}

void ReportTrajectoryText(const TrajectoryFigures& f, std::ostream& out) {
  out << "length " << Fixed(f.LengthMm, 1) << " mm, in bone " << Fixed(f.LengthInBoneMm, 1) << " mm";
  for (const auto& b : f.Bone) out << " [" << Fixed(b.FromMm, 1) << "-" << Fixed(b.ToMm, 1) << "]";
  out << "\n";
  for (const auto& t : f.Tissues) out << "  " << t.Name << ": " << Fixed(t.LengthMm, 1) << " mm\n";
  if (f.CorticalSurfaceShare >= 0) out << "cortical share of the tool's surface " << Fixed(100 * f.CorticalSurfaceShare, 1) << " %\n";
  if (f.Breach.Found)
    out << "breach " << Fixed(f.Breach.BreachMm, 1) << " mm at " << Fixed(f.Breach.DepthMm, 1) << " mm deep: Gertzbein-Robbins grade "
        << f.Breach.Grade << "\n";
  else
    out << "no breach\n";
  for (const auto& c : f.Clearances)
    out << "clearance from " << c.Name << " " << Fixed(c.ClearanceMm, 1) << " mm at " << Fixed(c.DepthMm, 1) << " mm deep"
        << (c.UnderMargin ? "  UNDER THE " + Fixed(c.SafetyMarginMm, 1) + " mm MARGIN" : "") << "\n";
}

int RunTrajectory(const std::vector<std::string>& args, bool screw, std::ostream& out, std::ostream& err) {
  ArgParser parser = TrajectoryParser(screw);
  if (const auto exitCode = parser.ParseCommand(args, out, err)) return *exitCode;
  const std::string command = screw ? "screw" : "trajectory";
  const auto start = std::chrono::steady_clock::now();
  PlanSession s;
  std::string error;
  if (!LoadPatient(parser, s, error)) return Fail(err, command, error);
  vtkRPTrajectoryNode* node = MakeTrajectory(parser, s, screw, error);
  if (!node) return parser.Has("plan") ? Fail(err, command, error) : (err << "roboplan plan " << command << ": " << error << "\n", 2);
  TrajectoryFigures figures;
  if (!s.Logic->ComputeFigures(node, figures, error)) return Fail(err, command, error);
  if (auto* sc = vtkRPScrewNode::SafeDownCast(node)) s.Logic->UpdateScrewModel(sc);
  nlohmann::json outputs = nlohmann::json::object();
  if (parser.Has("out")) {
    if (!WriteOut(s, node, parser.Get("out"), error)) return Fail(err, command, error);
    outputs["plan"] = parser.Get("out");
  }
  if (parser.Has("profile-chart")) {
    if (!WriteProfileChart(parser.Get("profile-chart"), figures, s.Logic->GetInputs().Tissue(), node->GetName(), error))
      return Fail(err, command, error);
    outputs["profileChart"] = parser.Get("profile-chart");
  }
  TrajectorySnapshot plan;
  vtkRPPlanningLogic::TrajectoryOf(node, plan);
  if (parser.Json()) {
    nlohmann::json doc = FiguresJson(figures, s.Logic->GetInputs().Tissue());
    doc["ok"] = true;
    doc["plan"] = TrajectoryJson(plan, node->GetIntendedTissue());
    doc["boneRule"] = s.Logic->GetInputs().BoneRule();
    doc["outputs"] = outputs;
    doc["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out << doc.dump(2) << "\n";
  } else {
    ReportTrajectoryText(figures, out);
  }
  return 0;
}

}  // namespace

// ---------------------------------------------------------------- propose
namespace {

ArgParser ProposeParser() {
  ArgParser parser("plan propose",
                   "Propose a trajectory's entry: every point of an entry region (a surface patch, a segment's "
                   "surface, within a sphere if asked) is scored by the clearance of the tool's path to the target "
                   "from every structure at risk; the best few, far enough apart, are printed (and the best written). "
                   "The region coloured by clearance is the risk map.");
  DeclarePatient(parser, true);
  parser.Option("target", "R,A,S", "target point (RAS, mm)").Point().Required();
  parser.Option("entry-region", "model|segment", "entry region: a model file (a surface patch) or a segment of --segmentation");
  parser.Option("entry-sphere", "R,A,S,r", "only the region within this sphere (centre and radius, mm); alone: the sphere's own surface")
      .Numbers();
  parser.Option("diameter", "mm", "tool diameter").Number().GreaterThan(0).Required();
  parser.Option("spacing", "mm", "candidate spacing: the region refined to this edge length", "1").Number().GreaterThan(0);
  parser.Flag("stay-in-bone", "only entries whose path stays in bone once in it");
  parser.Option("best", "n", "how many best entries", "5").Integer().AtLeast(1);
  parser.Option("threads", "n", "worker threads", "2").Integer().AtLeast(1);
  parser.Option("name", "text", "the proposed plan's name", "Proposed trajectory");
  parser.Option("out", "file", "write the best trajectory: .mrk.json, or a scene (.rpscene, .mrml, .mrb)")
      .Output(FileKind::Points, {".mrk.json", ".rpscene", ".mrml", ".mrb"});
  parser.Option("risk-map", "model", "the entry region with the point scalar clearanceMm (.vtp, .vtk...)").Output(FileKind::Model);
  parser.Option("risk-map-picture", "png", "picture of the risk map with the structures and the best trajectories")
      .Output(FileKind::Any, {".png"});
  return parser;
}

bool SetRegion(const ArgParser& parser, PlanSession& s, vtkRPPlanningLogic::ProposalOptions& options, std::string& error) {
  if (parser.Has("entry-sphere")) {
    const auto sphere = parser.GetDoubles("entry-sphere", 4);
    std::copy(sphere.begin(), sphere.begin() + 3, options.SphereCenter);
    options.SphereRadiusMm = sphere[3];
    if (!(sphere[3] > 0)) {
      error = "--entry-sphere: the radius must be > 0";
      return false;
    }
  }
  if (!parser.Has("entry-region")) {
    if (options.SphereRadiusMm <= 0) {
      error = "give --entry-region, --entry-sphere, or both";
      return false;
    }
    vtkRPPlanningLogic::ProposalOptions whole = options;
    whole.SphereRadiusMm = 0;
    return s.Logic->SetEntryRegion(SpherePolyData(options.SphereCenter, options.SphereRadiusMm), whole, error);
  }
  const std::string region = parser.Get("entry-region");
  if (!std::filesystem::exists(region)) return s.Logic->SetEntryRegionFromSegment(s.Segmentation, region, options, error);
  LoadResult result;
  auto* model = vtkRPModelNode::SafeDownCast(LoadSingleNode(s.Scene, region, result));
  if (!model) {
    error = "--entry-region: " + (result.Ok ? "'" + region + "' is not a model" : result.Error);
    return false;
  }
  model->SetName("Entry region");
  return s.Logic->SetEntryRegion(model, options, error);
}

int RunPropose(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  ArgParser parser = ProposeParser();
  if (const auto exitCode = parser.ParseCommand(args, out, err)) return *exitCode;
  PlanSession s;
  std::string error;
  if (!LoadPatient(parser, s, error)) return Fail(err, "propose", error);
  vtkRPPlanningLogic::ProposalOptions options;
  options.ToolDiameterMm = parser.GetDouble("diameter");
  options.SpacingMm = parser.GetDouble("spacing");
  options.StayInBone = parser.Has("stay-in-bone");
  options.Best = static_cast<int>(parser.GetInt("best"));
  options.Threads = static_cast<int>(parser.GetInt("threads"));
  if (!SetRegion(parser, s, options, error)) return Fail(err, "propose", error);
  const auto target = parser.GetDoubles("target", 3);
  ProposalResult result;
  if (!s.Logic->Propose(target.data(), options, result, error)) return Fail(err, "propose", error);
  std::vector<StructureAtRiskSnapshot> structures;  // the ones the proposal used (cached)
  if (!s.Logic->GetStructuresAtRiskSnapshot(structures, error)) return Fail(err, "propose", error);
  // The best entry as a plan.
  vtkNew<vtkRPTrajectoryNode> best;
  best->SetName(parser.Get("name"));
  const Vec3 entry = s.Logic->GetCandidates()[static_cast<size_t>(result.Best.front())];
  const double e[3] = {entry.x, entry.y, entry.z};
  best->SetEntryAndTarget(e, target.data());
  best->SetToolDiameterMm(options.ToolDiameterMm);
  best->SetPlannedOn(vtkRPPlanningLogic::VolumeIdentity(s.CT));
  s.Scene->AddNode(best);
  vtkRPModelNode* riskMap = s.Logic->UpdateRiskMap(result);
  nlohmann::json outputs = nlohmann::json::object();
  if (parser.Has("risk-map")) {
    if (!SaveDataFile(riskMap, parser.Get("risk-map"), error)) return Fail(err, "propose", error);
    outputs["riskMap"] = parser.Get("risk-map");
  }
  if (parser.Has("risk-map-picture")) {
    if (!WriteRiskMapPicture(parser.Get("risk-map-picture"), s.Logic->RiskMapPolyData(result), structures, target.data(),
                             s.Logic->GetCandidates(), result, error))
      return Fail(err, "propose", error);
    outputs["riskMapPicture"] = parser.Get("risk-map-picture");
  }
  if (parser.Has("out")) {
    if (!WriteOut(s, best, parser.Get("out"), error)) return Fail(err, "propose", error);
    outputs["plan"] = parser.Get("out");
  }
  ProposalRequest request;
  request.Target = {target[0], target[1], target[2]};
  request.ToolDiameterMm = options.ToolDiameterMm;
  request.Candidates = s.Logic->GetCandidates();
  request.StayInBone = options.StayInBone;
  if (parser.Json()) {
    nlohmann::json doc = ProposalJson(request, result, structures);
    doc["ok"] = true;
    doc["outputs"] = outputs;
    out << doc.dump(2) << "\n";
  } else {
    out << request.Candidates.size() << " candidate entries (spacing " << Fixed(result.SpacingMm, 2) << " mm) scored in "
        << Fixed(1000 * result.Seconds, 1) << " ms\n";
    for (size_t k = 0; k < result.Best.size(); ++k) {
      const auto& score = result.Scores[static_cast<size_t>(result.Best[k])];
      const Vec3& p = request.Candidates[static_cast<size_t>(result.Best[k])];
      out << k + 1 << ". entry " << Fixed(p.x, 1) << "," << Fixed(p.y, 1) << "," << Fixed(p.z, 1) << "  clearance "
          << Fixed(score.ClearanceMm, 1) << " mm (" << Fixed(score.SlackMm, 1) << " mm beyond the margin)\n";
    }
  }
  return 0;
}

}  // namespace

// ---------------------------------------------------------------- plane
namespace {

int RunPlane(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  ArgParser parser("plan plane",
                   "Plan a cut plane (a Slicer markups plane) and measure it: the bone volume on each side of the "
                   "plane, per bone, and the area of the cut.");
  DeclarePatient(parser, false);
  parser.Option("origin", "R,A,S", "a point of the plane (RAS, mm)").Point();
  parser.Option("normal", "R,A,S", "the plane's normal (need not be unit)").Point();
  parser.Option("size", "W,H", "the rectangle drawn (mm)", "100,100").Numbers();
  parser.Option("plan", "plane.mrk.json", "an existing plane (a markups plane) instead of --origin/--normal")
      .Input(FileKind::Points, {".mrk.json"});
  parser.Option("name", "text", "the plane's name", "Cut");
  parser.Option("out", "file", "write the plane: .mrk.json, or a scene (.rpscene, .mrml, .mrb)")
      .Output(FileKind::Points, {".mrk.json", ".rpscene", ".mrml", ".mrb"});
  if (const auto exitCode = parser.ParseCommand(args, out, err)) return *exitCode;
  PlanSession s;
  std::string error;
  if (!LoadPatient(parser, s, error)) return Fail(err, "plane", error);
  vtkRPCutPlaneNode* plane = nullptr;
  if (parser.Has("plan") == (parser.Has("origin") || parser.Has("normal"))) {
    err << "roboplan plan plane: give --origin and --normal, or --plan\n";
    return 2;
  }
  if (parser.Has("plan")) {
    LoadResult result;
    plane = vtkRPCutPlaneNode::SafeDownCast(LoadSingleNode(s.Scene, parser.Get("plan"), result));
    if (!plane) return Fail(err, "plane", result.Ok ? "'" + parser.Get("plan") + "' holds no plane" : result.Error);
  } else {
    vtkNew<vtkRPCutPlaneNode> created;
    created->SetName(parser.Get("name"));
    const auto origin = parser.GetDoubles("origin", 3), normal = parser.GetDoubles("normal", 3),
               size = parser.GetDoubles("size", 2);
    created->SetOrigin(origin.data());
    if (!created->SetNormal(normal.data())) return Fail(err, "plane", "the plane's normal is zero: it has no direction");
    created->SetSize(size[0], size[1]);
    created->SetPlannedOn(vtkRPPlanningLogic::VolumeIdentity(s.CT));
    plane = vtkRPCutPlaneNode::SafeDownCast(s.Scene->AddNode(created));
  }
  std::vector<vtkRPPlanningLogic::BoneCut> cuts;
  if (!s.Logic->ComputeCut(plane, cuts, error)) return Fail(err, "plane", error);
  if (parser.Has("out") && !WriteOut(s, plane, parser.Get("out"), error)) return Fail(err, "plane", error);
  double origin[3], normal[3];
  plane->GetOriginWorld(origin);
  plane->GetNormalWorld(normal);
  if (parser.Json()) {
    out << nlohmann::json{{"ok", true},
                          {"plane", {{"name", plane->GetName()}, {"origin", {origin[0], origin[1], origin[2]}},
                                     {"normal", {normal[0], normal[1], normal[2]}},
                                     {"sizeMm", {plane->GetSize()[0], plane->GetSize()[1]}}}},
                          {"bones", CutJson(cuts)}}
               .dump(2)
        << "\n";
  } else {
    for (const auto& c : cuts)
      out << c.Bone << ": " << Fixed(c.Figures.PositiveVolumeMm3 / 1000, 1) << " cm3 on the normal's side, "
          << Fixed(c.Figures.NegativeVolumeMm3 / 1000, 1) << " cm3 on the other, cut " << Fixed(c.Figures.CutAreaMm2 / 100, 1)
          << " cm2\n";
  }
  return 0;
}

}  // namespace

// ---------------------------------------------------------------- show
namespace {

nlohmann::json PlanNodeJson(vtkRPNode* node) {
  nlohmann::json j = {{"class", node->GetClassName()}, {"name", node->GetName()}, {"attributes", node->GetAttributes()}};
  TrajectorySnapshot plan;
  if (auto* trajectory = vtkRPTrajectoryNode::SafeDownCast(node)) {
    if (vtkRPPlanningLogic::TrajectoryOf(trajectory, plan)) {
      j.update(TrajectoryJson(plan, trajectory->GetIntendedTissue()));
      j["lengthMm"] = plan.LengthMm();
    }
    j["plannedOn"] = trajectory->GetPlannedOn();
  } else if (auto* plane = vtkRPCutPlaneNode::SafeDownCast(node)) {
    double origin[3], normal[3], x[3];
    plane->GetOriginWorld(origin), plane->GetNormalWorld(normal), plane->GetXAxisWorld(x);
    j["origin"] = {origin[0], origin[1], origin[2]};
    j["normal"] = {normal[0], normal[1], normal[2]};
    j["xAxis"] = {x[0], x[1], x[2]};
    j["sizeMm"] = {plane->GetSize()[0], plane->GetSize()[1]};
  }
  if (auto* markups = vtkRPMarkupsNode::SafeDownCast(node)) {
    nlohmann::json points = nlohmann::json::array();
    for (int i = 0; i < markups->GetNumberOfControlPoints(); ++i) {
      double world[3];
      markups->GetNthControlPointPositionWorld(i, world);
      points.push_back({{"label", markups->GetNthControlPoint(i).Label}, {"position", {world[0], world[1], world[2]}}});
    }
    j["controlPoints"] = points;
  }
  return j;
}

int RunShow(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  ArgParser parser("plan show", "Open plan files (.mrk.json) and scenes (.rpscene, .mrml, .mrb) and list their plans: "
                                "trajectories, screws, cut planes and structures at risk, in world RAS.");
  parser.Positional("files", "plan files and scenes", true, true);
  parser.Option("out", "file", "write what was read: .mrk.json (one plan) or a scene").Output(FileKind::Points);
  if (const auto exitCode = parser.ParseCommand(args, out, err)) return *exitCode;
  PlanSession s;
  for (const std::string& path : parser.GetAll("files")) {
    const LoadResult result = LoadPath(s.Scene, path);
    if (!result.Ok) return Fail(err, "show", result.Error);
  }
  nlohmann::json plans = nlohmann::json::array(), structures = nlohmann::json::array();
  std::vector<vtkRPNode*> planNodes = s.Scene->GetNodesByClass("vtkRPPlanNode");
  for (vtkRPNode* node : planNodes) plans.push_back(PlanNodeJson(node));
  for (const auto& structure : s.Logic->GetStructuresAtRisk())
    structures.push_back({{"name", structure.Name}, {"safetyMarginMm", structure.SafetyMarginMm},
                          {"segment", structure.SegmentID}, {"node", structure.Node->GetName()}});
  std::string error;
  if (parser.Has("out")) {
    if (HasExtension(parser.Get("out"), ".mrk.json") && planNodes.size() != 1)
      return Fail(err, "show", "a .mrk.json holds one plan; these files hold " + std::to_string(planNodes.size()));
    if (!WriteOut(s, planNodes.empty() ? nullptr : planNodes.front(), parser.Get("out"), error)) return Fail(err, "show", error);
  }
  if (parser.Json()) {
    out << nlohmann::json{{"ok", true}, {"plans", plans}, {"structuresAtRisk", structures}}.dump(2) << "\n";
  } else {
    for (const auto& p : plans) out << p["class"].get<std::string>() << " '" << p["name"].get<std::string>() << "'\n";
    for (const auto& p : structures) out << "structure at risk '" << p["name"].get<std::string>() << "'\n";
  }
  return 0;
}

}  // namespace

int RunPlanCommand(const std::vector<std::string>& arguments, std::ostream& out, std::ostream& err) {
  const std::map<std::string, std::function<int(const std::vector<std::string>&)>> commands = {
      {"trajectory", [&](const std::vector<std::string>& a) { return RunTrajectory(a, false, out, err); }},
      {"screw", [&](const std::vector<std::string>& a) { return RunTrajectory(a, true, out, err); }},
      {"propose", [&](const std::vector<std::string>& a) { return RunPropose(a, out, err); }},
      {"plane", [&](const std::vector<std::string>& a) { return RunPlane(a, out, err); }},
      {"show", [&](const std::vector<std::string>& a) { return RunShow(a, out, err); }}};
  const std::string usage =
      "usage: roboplan plan <trajectory|screw|propose|plane|show> [options] (each with --help)\n"
      "  trajectory  plan a tool's path from entry to target and measure it against the CT\n"
      "  screw       the same for a screw (diameter, length, head), with its model\n"
      "  propose     score every entry of a region against the structures at risk; the best few and a risk map\n"
      "  plane       plan a cut: bone volume each side and the cut's area, per bone\n"
      "  show        list the plans of plan files and scenes\n";
  if (arguments.empty() || arguments[0] == "--help" || arguments[0] == "-h") {
    (arguments.empty() ? err : out) << usage;
    return arguments.empty() ? 2 : 0;
  }
  const auto it = commands.find(arguments[0]);
  if (it == commands.end()) {
    err << "roboplan plan: unknown sub-command '" << arguments[0] << "'\n" << usage;
    return 2;
  }
  try {
    return it->second(std::vector<std::string>(arguments.begin() + 1, arguments.end()));
  } catch (const std::exception& e) {  // a value the parser let through but a reader refused
    err << "roboplan plan " << arguments[0] << ": " << e.what() << "\n";
    return 2;
  }
}

}  // namespace rp
