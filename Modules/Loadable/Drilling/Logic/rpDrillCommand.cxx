#include "rpDrillCommand.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkDataArray.h>
#include <vtkPolyData.h>

#include "rpArgParser.h"
#include "rpBlockMesher.h"
#include "rpDrillProtection.h"
#include "rpExecutionScoreJson.h"
#include "rpGuidedDrill.h"
#include "rpModelIO.h"
#include "rpPlanFixtures.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpSegmentationIO.h"
#include "rpServoLoadReport.h"
#include "rpSimulatedDevice.h"
#include "rpTunnelPicture.h"
#include "rpVolumeFiles.h"
#include "rpVolumeIO.h"
#include "vtkRPDrillingLogic.h"
#include "vtkRPScene.h"
#include "vtkRPSegmentationNode.h"

namespace rp {

double CapsuleVolumeInBox(const Vec3& a, const Vec3& b, double r, const Vec3& lo, const Vec3& hi, bool& exact) {
  const Vec3 clo = Min(a, b) - Vec3{r, r, r}, chi = Max(a, b) + Vec3{r, r, r};
  const double length = Norm(b - a);
  if (clo.x >= lo.x && clo.y >= lo.y && clo.z >= lo.z && chi.x <= hi.x && chi.y <= hi.y && chi.z <= hi.z) {
    exact = true;
    return M_PI * r * r * length + 4.0 / 3.0 * M_PI * r * r * r;
  }
  exact = false;
  const Vec3 qlo = Max(clo, lo), qhi = Min(chi, hi);
  if (!(qlo.x < qhi.x && qlo.y < qhi.y && qlo.z < qhi.z)) return 0;
  // Midpoint rule on a grid of about 4·10⁷ points at most (r/40 or finer).
  const Vec3 size = qhi - qlo;
  double step = r / 40;
  while (size.x * size.y * size.z / (step * step * step) > 4e7) step *= 1.25;
  const int n[3] = {std::max(1, int(std::ceil(size.x / step))), std::max(1, int(std::ceil(size.y / step))),
                    std::max(1, int(std::ceil(size.z / step)))};
  const Vec3 d{size.x / n[0], size.y / n[1], size.z / n[2]};
  const Vec3 ab = b - a;
  const double ab2 = std::max(Norm2(ab), 1e-300);
  long long inside = 0;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const Vec3 p = qlo + Vec3{(i + 0.5) * d.x, (j + 0.5) * d.y, (k + 0.5) * d.z};
        const double t = std::clamp(Dot(p - a, ab) / ab2, 0.0, 1.0);
        inside += Norm2(p - (a + ab * t)) <= r * r;
      }
  return inside * d.x * d.y * d.z;
}

double FarthestChangeFromPath(const DrillVolume& volume, const std::vector<Vec3>& path) {
  std::vector<Vec3> points;
  for (const Vec3& p : path)
    if (points.empty() || Norm(p - points.back()) >= 0.05) points.push_back(p);
  if (!path.empty() && (points.empty() || Norm(path.back() - points.back()) > 0)) points.push_back(path.back());
  if (points.size() == 1) points.push_back(points.front());
  double farthest = 0;
  for (size_t s = 0; s < volume.AllocatedBlocks(); ++s) {
    const auto c = volume.BlockCoordinate(static_cast<int32_t>(s));
    const auto* now = volume.BlockDensities(static_cast<int32_t>(s));
    const uint8_t* original = volume.BlockOriginal(static_cast<int32_t>(s));
    for (int v = 0; v < DrillVolume::BlockVoxels; ++v) {
      if (now[v].load(std::memory_order_relaxed) == original[v]) continue;
      const Vec3 p = volume.Grid().Center(c[0] * DrillVolume::BlockEdge + (v & 7), c[1] * DrillVolume::BlockEdge + ((v >> 3) & 7),
                                          c[2] * DrillVolume::BlockEdge + (v >> 6));
      double nearest = HUGE_VAL;
      for (size_t i = 0; i + 1 < points.size(); ++i) {
        const Vec3 ab = points[i + 1] - points[i];
        const double t = Norm2(ab) > 0 ? std::clamp(Dot(p - points[i], ab) / Norm2(ab), 0.0, 1.0) : 0.0;
        nearest = std::min(nearest, Norm2(p - (points[i] + ab * t)));
      }
      farthest = std::max(farthest, std::sqrt(nearest));
    }
  }
  return farthest;
}

namespace {

Vec3 ToVec3(const std::vector<double>& v) { return {v[0], v[1], v[2]}; }
nlohmann::json Json(const Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

// The servo's timing with its conditions: how ticks were timed, on what, and what the machine
// did to the servo thread meanwhile (steal, preemption, faults), so a figure says where it came from.
nlohmann::json ServoJson(const DrillRunResult& result, const DrillRunOptions& run) {
  const MachineLoad& load = result.Load;
  nlohmann::json conditions = {
      {"mode", run.Realtime ? "realtime: the 1 kHz servo thread (rp::ServoLoop), wall clock per tick"
                            : "scripted: ticks on one thread, thread CPU time per tick"},
      {"cpus", AvailableCpus()},
      {"loadAverage1min", load.LoadAverage},
#ifdef NDEBUG
      {"optimized", true},
#else
      {"optimized", false},
#endif
  };
  nlohmann::json servo = {{"tickP50Us", result.TickCompute.P50Us},
                          {"tickP99Us", result.TickCompute.P99Us},
                          {"tickMaxUs", result.TickCompute.MaxUs},
                          {"ticks", result.Ticks},
                          {"conditions", conditions},
                          {"load", MachineLoadJson(load)}};
  if (run.Realtime) {
    servo["periodP99Us"] = result.Servo.Period.P99Us;
    servo["latenessP99Us"] = result.Servo.Lateness.P99Us;
    servo["missedDeadlines"] = result.Servo.MissedDeadlines;
    servo["overruns"] = result.Servo.Overruns;
    servo["realTimePriority"] = result.Servo.RealTimePriority;
    servo["missesReading"] = MachineLoadReading(load, result.Servo.MissedDeadlines, result.Servo.Overruns);
  }
  return servo;
}

// What `roboplan drill` was asked: every option, read and checked once.
struct DrillRequest {
  bool Json = false, Replay = false, Block = false, Realtime = false;
  bool VoxelGiven = false, FeedGiven = false, HasCT = false, HasModel = false, HasPicture = false;
  int Cpu = -1;
  bool Shield = false;
  double Radius = 0, Speed = 0, Voxel = 0.3, Rpm = 60000, Feed = 2, Shell = 0, Margin = 0, Timeout = -1;
  Vec3 From, To, BlockLo{-20, -20, -20}, BlockHi{20, 20, 20};
  std::string Segmentation, CT, Materials, Record, ReplayPath, Model, Picture;
  std::vector<std::string> Segments, Protect;
  // --plan: the plan's trajectory drilled by the simulated hand with its fixtures, then scored.
  bool HasPlan = false;
  std::string Plan, Trajectory, Fixtures = "none";
  double Tremor = 0, Drift = 0;
  uint64_t Seed = 1;
};

ArgParser DrillParser() {
  ArgParser parser("drill",
                   "Drill a straight stroke into a bone with a spherical burr at the servo rate (simulated device): removed "
                   "volume per tissue, forces, servo and display timings.");
  parser.Positional("segmentation", "bone segmentation (.seg.nrrd, or a labelmap volume)", false)
      .Flag("block", "drill an analytic block of bone instead (known volume of the stroke)")
      .Option("segment", "ID", "bone segment to drill: ID, name or label value (repeatable)")
      .Option("protect", "ID[:MM]", "protected segment (a structure at risk, with its safety margin in mm): the burr "
                                    "stops when it reaches it (repeatable)")
      .Option("ct", "FILE", "CT volume or DICOM folder: cortical / trabecular bone by HU (materials.json ctMinHU)")
      .Option("burr-radius", "MM", "burr radius (1-3 mm for the usual burrs)")
      .Option("from", "R,A,S", "where the stroke starts (the burr starts there, cutting), RAS mm")
      .Option("to", "R,A,S", "where the stroke ends, RAS mm")
      .Option("speed", "MM/S", "hand speed along the stroke")
      .Option("voxel", "MM", "drill voxel size", "0.3")
      .Option("rpm", "N", "burr speed", "60000")
      .Option("feed", "MM/S", "cutting speed into hardness-1 bone at the device's maximum force and 60000 rpm", "2")
      .Option("block-bounds", "R0,A0,S0,R1,A1,S1", "the --block's box (RAS mm)", "-20,-20,-20,20,20,20")
      .Option("shell", "MM", "--block: a cortical shell this thick around a trabecular core (0: all cortical)", "0")
      .Option("margin", "MM", "build the voxel bone only within this distance of the stroke (0: the whole segment)", "0")
      .Option("materials", "FILE", "material table (default: Resources/Materials/materials.json)")
      .Option("timeout", "S", "give up after this much session time (default: three times the stroke at the feed rate + 5 s; with --plan, 120 s: "
                                 "the run otherwise ends when the burr arrives or stalls)")
      .Option("record", "FILE", "write the drill path (time, burr, proxy, force, removed volume per tick)")
      .Option("replay", "FILE", "drive the burr along a recorded drill path instead of --from/--to")
      .Option("model", "FILE", "write the drilled bone's surface (" + ModelFileExtensionsText() + ")")
      .Option("picture", "FILE.png", "render a picture of the tunnel (needs a display or Xvfb)")
      .Option("plan", "FILE", "drill this plan's trajectory (a .mrk.json line, or a scene with its plan and structures at "
                               "risk) with the simulated hand, and score the execution against it")
      .Option("trajectory", "NAME", "--plan: which trajectory (node ID or name; default the first)")
      .Option("fixtures", "LIST", "--plan: the virtual fixtures on: axis, depth, forbidden, surface (comma-separated) or none",
              "none")
      .Option("tremor", "MM", "--plan: the hand's physiological tremor, RMS (8-12 Hz)", "0")
      .Option("drift", "MM/S", "--plan: the hand's slow drift speed", "0")
      .Option("seed", "N", "--plan: the seed of the hand's tremor and drift (the same seed, the same hand)", "1")
      .Option("cpu", "N", "--realtime: pin the servo thread to CPU N and move the other threads off it (-1: not pinned)", "-1")
      .Flag("shield", "with --cpu: also keep every other process's threads off that CPU while the servo runs")
      .Flag("realtime", "run the 1 kHz servo thread and the 30 Hz display thread on the wall clock (default: the same "
                        "ticks scripted on one thread, as fast as the CPU allows)");
  return parser;
}

// The options' values that do not depend on one another's checks (exit code 2 on a malformed one).
bool ReadDrillNumbers(const ArgParser& parser, DrillRequest& q, std::ostream& err) {
  try {
    q.Voxel = parser.GetDouble("voxel");
    q.Cpu = static_cast<int>(parser.GetDouble("cpu"));
    q.Shield = parser.Has("shield");
    if (q.Shield && q.Cpu < 0) throw std::invalid_argument("--shield needs --cpu N (the CPU to keep the other processes off)");
    q.Rpm = parser.GetDouble("rpm");
    q.Feed = parser.GetDouble("feed");
    q.Shell = parser.GetDouble("shell");
    q.Margin = parser.GetDouble("margin");
    if (parser.Has("timeout")) q.Timeout = parser.GetDouble("timeout");
    const auto bounds = parser.GetDoubles("block-bounds", 6);
    q.BlockLo = {bounds[0], bounds[1], bounds[2]};
    q.BlockHi = {bounds[3], bounds[4], bounds[5]};
    q.Tremor = parser.GetDouble("tremor");
    q.Drift = parser.GetDouble("drift");
    q.Seed = static_cast<uint64_t>(parser.GetDouble("seed"));
    if (q.HasPlan) {  // the stroke and the burr come from the plan unless given
      if (parser.Has("burr-radius")) q.Radius = parser.GetDouble("burr-radius");
      q.Speed = parser.Has("speed") ? parser.GetDouble("speed") : 2.5;
    } else if (!q.Replay) {
      for (const char* required : {"burr-radius", "from", "to", "speed"})
        if (!parser.Has(required)) throw std::invalid_argument(std::string("--") + required + " is required (or --replay)");
      q.Radius = parser.GetDouble("burr-radius");
      q.Speed = parser.GetDouble("speed");
      q.From = ToVec3(parser.GetDoubles("from", 3));
      q.To = ToVec3(parser.GetDoubles("to", 3));
    }
  } catch (const std::exception& e) {
    err << "roboplan drill: " << e.what() << "\n";
    return false;
  }
  return true;
}

// The first range or combination the request breaks, or "" when it breaks none.
std::string DrillRequestProblem(const DrillRequest& q, bool hasSegmentation, bool hasSegment) {
  if (q.Block == hasSegmentation) return "give either --block or a segmentation file (with --segment)";
  if (!q.Block && !hasSegment) return "--segment ID is required with a segmentation";
  if (!(q.Voxel >= 0.05 && q.Voxel <= 5)) return "--voxel must be in [0.05, 5] mm";
  if (q.HasPlan && q.Replay) return "give --plan or --replay, not both";
  if (!(q.Tremor >= 0 && q.Tremor <= 5) || !(q.Drift >= 0 && q.Drift <= 20))
    return "--tremor must be in [0, 5] mm and --drift in [0, 20] mm/s";
  if (!q.Replay && !q.HasPlan && !(q.Radius >= 0.25 && q.Radius <= 10)) return "--burr-radius must be in [0.25, 10] mm";
  if (!q.Replay && !(q.Speed > 0 && q.Speed <= 2000)) return "--speed must be in (0, 2000] mm/s";
  if (!(q.Rpm >= 0 && q.Rpm <= 200000) || !(q.Feed > 0 && q.Feed <= 1000) || q.Shell < 0 || q.Margin < 0)
    return "--rpm must be in [0, 200000], --feed positive, --shell and --margin not negative";
  if (q.Block && !(q.BlockLo.x < q.BlockHi.x && q.BlockLo.y < q.BlockHi.y && q.BlockLo.z < q.BlockHi.z))
    return "--block-bounds must give a box with R0 < R1, A0 < A1, S0 < S1";
  return "";
}

// Parses and checks the command line; an exit code when the command ends here (help, bad options).
std::optional<int> ParseDrillRequest(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
                                     DrillRequest& q) {
  ArgParser parser = DrillParser();
  if (const auto exitCode = parser.ParseCommand(args, out, err)) return *exitCode;
  q.Json = parser.Json();
  q.Replay = parser.Has("replay");
  q.HasPlan = parser.Has("plan");
  q.Plan = parser.Get("plan");
  q.Trajectory = parser.Get("trajectory");
  q.Fixtures = parser.Get("fixtures");
  if (!ReadDrillNumbers(parser, q, err)) return 2;
  q.Block = parser.Has("block");
  const std::string problem = DrillRequestProblem(q, parser.Has("segmentation"), parser.Has("segment"));
  if (!problem.empty()) {
    err << "roboplan drill: " << problem << "\n";
    return 2;
  }
  q.Realtime = parser.Has("realtime");
  q.VoxelGiven = parser.Has("voxel");
  q.FeedGiven = parser.Has("feed");
  q.HasCT = parser.Has("ct");
  q.HasModel = parser.Has("model");
  q.HasPicture = parser.Has("picture");
  q.Segmentation = parser.Get("segmentation");
  q.CT = parser.Get("ct");
  q.Materials = parser.Get("materials");
  q.Record = parser.Get("record");
  q.ReplayPath = parser.Get("replay");
  q.Model = parser.Get("model");
  q.Picture = parser.Get("picture");
  q.Segments = parser.GetAll("segment");
  q.Protect = parser.GetAll("protect");
  return std::nullopt;
}

// What a drill run made: the logic (bone, session, drilled mesh), the replayed recording, the run.
struct DrillWork {
  vtkSmartPointer<vtkRPDrillingLogic> Logic = vtkSmartPointer<vtkRPDrillingLogic>::New();
  std::shared_ptr<const PlanSnapshot> Plan;  // --plan
  TrajectorySnapshot Trajectory;
  std::shared_ptr<const FixtureSet> Fixtures;
  GuidedDrillResult Guided;
  DrillRecording Recording;
  std::vector<std::string> Segments;  // the drilled segments' IDs ("block" for --block)
  DrillRunOptions Run;
  DrillRunResult Result;
};

int Fail(std::ostream& err, const std::string& message) {
  err << "roboplan drill: " << message << "\n";
  return 1;
}

// The --replay recording: the stroke, burr and (unless given) voxel and feed come from it.
int ReadReplay(DrillRequest& q, DrillWork& s, std::ostream& err) {
  std::string error;
  if (!DrillRecording::Read(q.ReplayPath, s.Recording, error)) return Fail(err, error);
  q.From = s.Recording.Lines.front().Record.Hip;
  q.To = s.Recording.Lines.back().Record.Hip;
  q.Radius = s.Recording.Lines.front().Record.Radius;
  if (s.Recording.Info.Voxel > 0 && !q.VoxelGiven) q.Voxel = s.Recording.Info.Voxel;
  if (s.Recording.Info.FeedRate > 0 && !q.FeedGiven) q.Feed = s.Recording.Info.FeedRate;
  return 0;
}

// --plan: the plan file into the scene, its trajectory as the stroke (and the burr, unless given).
bool LoadDrillPlan(DrillRequest& q, DrillWork& s, vtkRPScene* scene, std::ostream& err) {
  std::string error;
  s.Plan = LoadPlan(scene, q.Plan, error);
  const TrajectorySnapshot* t = s.Plan ? ChooseTrajectory(*s.Plan, q.Trajectory, error) : nullptr;
  if (!t) return Fail(err, "--plan " + q.Plan + ": " + error) == 0;
  s.Trajectory = *t;
  q.From = t->Entry;
  q.To = t->Target;
  if (!(q.Radius > 0)) q.Radius = 0.5 * t->ToolDiameterMm;
  if (!(q.Radius >= 0.25 && q.Radius <= 10)) return Fail(err, "the plan's tool diameter gives a burr radius outside [0.25, 10] mm") == 0;
  return true;
}

// --plan: the --protect segments become structures at risk (their margins), one notion with the
// plan's; with the segmentation in the scene, the plan's snapshot takes them with its own.
bool FlagStructuresAtRisk(const DrillRequest& q, vtkRPSegmentationNode* segmentation, const DrillSegments& guarded,
                          DrillWork& s, std::ostream& err) {
  for (size_t i = 0; i < guarded.IDs.size() && i < q.Protect.size(); ++i) {
    const size_t colon = q.Protect[i].rfind(':');
    Segment segment = *segmentation->FindSegment(guarded.IDs[i]);
    segment.Protection.Protected = true;
    try {
      if (colon != std::string::npos) segment.Protection.SafetyMarginMm = std::stod(q.Protect[i].substr(colon + 1));
    } catch (const std::exception&) {
      Fail(err, "--protect " + q.Protect[i] + ": the margin after ':' is not a number of mm");
      return false;
    }
    segmentation->SetSegment(segment);
  }
  s.Logic->GetScene()->AddNode(segmentation);
  std::string error;
  s.Plan = SnapshotPlan(s.Logic->GetScene(), error);
  if (!s.Plan) Fail(err, error);
  return static_cast<bool>(s.Plan);
}

// The voxel bone (and protected surface) from the segmentation file's segments, in the logic.
int BuildSegmentedBone(const DrillRequest& q, DrillWork& s, TerminalProgress& progress, std::ostream& err) {
  std::string error;
  vtkNew<vtkRPSegmentationNode> segmentation;
  if (!ReadSegmentationOrLabelmap(q.Segmentation, segmentation, error)) return Fail(err, error);
  DrillBoneSource source;
  source.Labels = FromNode(segmentation);
  DrillSegments bone, guarded;
  std::vector<std::string> protect;  // the segments; their margins (":MM") flag them as structures at risk
  for (const std::string& ref : q.Protect) protect.push_back(ref.substr(0, ref.rfind(':') == std::string::npos ? ref.size() : ref.rfind(':')));
  if (!FindDrillSegments(segmentation, q.Segments, bone, error) || !FindDrillSegments(segmentation, protect, guarded, error))
    return Fail(err, error);
  if (q.HasPlan && !FlagStructuresAtRisk(q, segmentation, guarded, s, err)) return 1;
  source.BoneLabels = bone.Labels;
  source.BoneTissues = bone.Tissues;
  source.ProtectedLabels = guarded.Labels;
  source.ProtectedTissues = guarded.Tissues;
  if (q.HasCT && !ReadVolume(q.CT, source.CT, error)) return Fail(err, "the CT: " + error);
  source.Spacing = q.Voxel;
  if (q.Margin > 0) {
    const Vec3 pad{q.Margin + q.Radius, q.Margin + q.Radius, q.Margin + q.Radius};
    source.HasRegion = true;
    source.RegionLo = Min(q.From, q.To) - pad;
    source.RegionHi = Max(q.From, q.To) + pad;
  }
  s.Segments = bone.IDs;
  if (!s.Logic->BuildBone(source, bone.Names, error,
                          [&](double f, const std::string& m) { progress.Report(0.3 * f, "voxel bone: " + m); }))
    return Fail(err, error);
  return 0;
}

// Runs the plan's trajectory with the simulated hand and the fixtures asked for, and scores it.
int DrivePlannedDrill(const DrillRequest& q, DrillWork& s, TerminalProgress& progress, std::ostream& err) {
  std::string error;
  s.Logic->SetTouchOtherModels(false);
  ProtectRegions(*s.Logic->GetBone(), ProtectedRegionsOf(*s.Plan));
  PlanFixtureChoice choice;
  choice.Trajectory = s.Trajectory.NodeID;
  if (!ParseFixtureKinds(q.Fixtures, choice, error) || !(s.Fixtures = BuildPlanFixtures(*s.Plan, choice, error)))
    return Fail(err, "--fixtures " + q.Fixtures + ": " + error);
  GuidedDrillOptions o;
  if (!TrajectoryAxis::Make(s.Trajectory.Entry, s.Trajectory.Target, o.Plan, error)) return Fail(err, error);
  o.PlanDiameterMm = s.Trajectory.ToolDiameterMm;
  o.BurrRadiusMm = q.Radius;
  o.Rpm = q.Rpm;
  o.FeedRate = q.Feed;
  o.SpeedMmPerS = q.Speed;
  o.Noise.TremorMm = q.Tremor;
  o.Noise.DriftMmPerS = q.Drift;
  o.Noise.Seed = q.Seed;
  o.Fixtures = s.Fixtures->Count() > 0 ? s.Fixtures : nullptr;
  o.Structures = ScoredStructuresOf(*s.Plan);
  o.Realtime = q.Realtime;
  o.Loop.RequestRealTimePriority = q.Realtime;
  o.Loop.CpuAffinity = q.Cpu;
  o.Loop.ShieldCpu = q.Shield;
  o.RecordPath = q.Record;
  if (q.Timeout > 0) o.MaxSeconds = q.Timeout;
  progress.Report(0.3, "drilling the plan");
  if (!RunGuidedDrill(s.Logic, o, s.Guided, error)) return Fail(err, error);
  s.Result = s.Guided.Run;
  s.Run.Realtime = q.Realtime;
  return 0;
}

// The burr's path and its on/off, radius and rpm over time: the straight stroke, or the recording.
int PlanPath(const DrillRequest& q, const DrillWork& s, WaypointTrajectory& path, std::function<DrillControl(double)>& schedule,
             std::ostream& err) {
  std::string error;
  if (q.Replay) {
    std::vector<double> times;
    std::vector<Vec3> points;
    for (const DrillRecordLine& l : s.Recording.Lines) {
      times.push_back(l.Record.Time);
      points.push_back(l.Record.Hip);
    }
    if (!path.Set(times, points, error)) return Fail(err, q.ReplayPath + ": " + error);
    const auto* lines = &s.Recording.Lines;
    schedule = [lines](double t) {
      auto it = std::upper_bound(lines->begin(), lines->end(), t,
                                 [](double time, const DrillRecordLine& l) { return time < l.Record.Time; });
      const DrillRecordLine& l = it == lines->begin() ? lines->front() : *(it - 1);
      return DrillControl{(l.Record.Flags & DrillRecordFlags::BurrOn) != 0, l.Record.Radius, l.Rpm};
    };
  } else {
    path.Set({0.0, 1e-3, 1e-3 + std::max(Norm(q.To - q.From), 1e-6) / q.Speed}, {q.From, q.From, q.To}, error);
  }
  return 0;
}

// The stroke in the logic: the simulated hand along the path (RAS), the burr placed at --from,
// the run to its end.
int DriveDrill(const DrillRequest& q, DrillWork& s, TerminalProgress& progress, std::ostream& err) {
  std::string error;
  const DrillControl on{true, q.Radius, q.Rpm};
  std::function<DrillControl(double)> schedule = [on](double) { return on; };
  auto path = std::make_shared<WaypointTrajectory>();
  if (const int code = PlanPath(q, s, *path, schedule, err)) return code;
  vtkRPDrillingLogic* logic = s.Logic;
  logic->SetSimulatedTrajectory(path);
  logic->SetTouchOtherModels(false);  // the bone alone
  DrillServoOptions servo;
  servo.FeedRate = q.Feed;
  servo.RampSeconds = 0;  // the burr starts in the bone: no force ramp to hide a jump
  logic->SetServoOptions(servo);
  ServoLoop::Options loop;
  loop.RequestRealTimePriority = q.Realtime;
  loop.CpuAffinity = q.Cpu;
  loop.ShieldCpu = q.Shield;
  logic->SetLoopOptions(loop);
  logic->SetRecordPath(q.Record);
  DrillControl start = q.Replay ? schedule(0) : on;
  if (q.Replay && !s.Recording.Info.StartCut) start.BurrOn = false;  // a session that began outside the bone
  logic->PlaceBurr(q.From, start);

  DrillRunOptions& run = s.Run;
  run.Realtime = q.Realtime;
  run.Schedule = schedule;
  const double length = Norm(q.To - q.From);
  const double tolerance = std::max(0.01, 0.05 * q.Voxel);
  const Vec3 to = q.To;
  if (q.Replay) {
    run.MaxSeconds = s.Recording.Lines.back().Record.Time + 1e-3;
  } else {
    run.MaxSeconds = q.Timeout > 0 ? q.Timeout : 3.0 * length / std::min(q.Speed, q.Feed) + 5.0;
    run.Finished = [to, tolerance](const DrillState& state) { return Norm(state.Proxy - to) < tolerance || state.Stopped; };
  }
  run.MeshEveryFrame = run.Realtime;  // scripted: only the last mesh is written or pictured
  run.Progress = [&](double f, const std::string& m) { progress.Report(0.3 + 0.65 * f, m); };
  if (!logic->RunSimulated(run, s.Result, error)) return Fail(err, error);
  return 0;
}

// Runs the drill the request describes: the bone in the logic, then the stroke.
int RunDrillSession(DrillRequest& q, DrillWork& s, vtkRPScene* scene, TerminalProgress& progress, std::ostream& err) {
  std::string error;
  if (q.Replay)
    if (const int code = ReadReplay(q, s, err)) return code;
  s.Logic->SetScene(scene);
  s.Logic->SetMaterialsPath(q.Materials);
  if (q.HasPlan && !LoadDrillPlan(q, s, scene, err)) return 1;
  if (q.Block) {
    s.Segments = {"block"};
    if (!s.Logic->BuildBlockBone(q.BlockLo, q.BlockHi, q.Shell, q.Voxel, error)) return Fail(err, error);
  } else if (const int code = BuildSegmentedBone(q, s, progress, err)) {
    return code;
  }
  if (const int code = q.HasPlan ? DrivePlannedDrill(q, s, progress, err) : DriveDrill(q, s, progress, err)) return code;
  progress.Report(0.97, "measuring");
  return 0;
}

// The figures a run's report gives, measured once for the JSON and the text.
struct DrillFigures {
  double Length = 0;
  bool Reached = false;
  std::string StopReason;
  std::vector<double> ContourMs, AssembleMs;
  double MeanBlocks = 0, WholeMs = 0;
  size_t WholeTriangles = 0;
  double Peak = 0, CuttingForce = 0;
  size_t Clamped = 0, CuttingTicks = 0;
};

DrillFigures MeasureDrill(const DrillRequest& q, const DrillWork& session) {
  DrillFigures g;
  const DrillState& s = session.Result.Final;
  g.Length = Norm(q.To - q.From);
  g.Reached = Norm(s.Proxy - q.To) < std::max(0.01, 0.05 * q.Voxel);
  g.StopReason = q.Replay ? "replayed" : g.Reached ? "reached" : (s.Stopped ? "protected" : "timeout");
  DisplayTimings frames = SplitDisplayFrames(session.Result.Frames);
  g.ContourMs = std::move(frames.ContourMs);
  g.AssembleMs = std::move(frames.AssembleMs);
  for (double b : frames.Blocks) g.MeanBlocks += b / std::max<size_t>(1, frames.Blocks.size());
  // The whole bone contoured from scratch, once, for comparison (same code, every block).
  BlockMesher whole(*session.Logic->GetBone());
  const auto wholeStart = std::chrono::steady_clock::now();
  whole.ContourAll();
  g.WholeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wholeStart).count();
  g.WholeTriangles = whole.TriangleCount();
  for (const DrillRecordLine& l : session.Result.Records) {
    const double f = Norm(l.Record.Force);
    g.Peak = std::max(g.Peak, f);
    g.Clamped += (l.Record.Flags & DrillRecordFlags::Clamped) != 0;
    if (l.Record.Flags & DrillRecordFlags::Cutting) g.CuttingForce += f, ++g.CuttingTicks;
  }
  return g;
}

nlohmann::json DrillJson(const DrillRequest& q, const DrillWork& session, const DrillFigures& g) {
  const DrillState& s = session.Result.Final;
  const DrillRunResult& result = session.Result;
  const DrillBoneReport& built = session.Logic->GetBoneReport();
  const std::vector<Material>& materials = session.Logic->GetMaterials();
  nlohmann::json removedByTissue = nlohmann::json::object(), volumeByTissue = nlohmann::json::object();
  for (size_t m = 0; m < materials.size(); ++m) {
    removedByTissue[materials[m].Tissue] = s.RemovedMm3[m];
    volumeByTissue[materials[m].Tissue] = m < built.VolumeMm3.size() ? built.VolumeMm3[m] : 0.0;
  }
  const double farthest = FarthestChangeFromPath(*session.Logic->GetBone(), {q.From, q.To});
  nlohmann::json doc = {
      {"bone",
       {{"source", q.Block ? std::string("block") : q.Segmentation},
        {"segments", session.Segments},
        {"voxelMm", q.Voxel},
        {"gridVoxels", built.GridVoxels},
        {"storedBlocks", built.StoredBlocks},
        {"memoryMB", built.MemoryMB},
        {"buildSeconds", built.Seconds},
        {"volumeMm3", volumeByTissue},
        {"materialsFromCT", built.UsedCT}}},
      {"burr", {{"radiusMm", q.Radius}, {"rpm", q.Rpm}, {"feedRateMmPerS", q.Feed}}},
      {"stroke",
       {{"from", Json(q.From)},
        {"to", Json(q.To)},
        {"lengthMm", g.Length},
        {"speedMmPerS", q.Replay ? 0.0 : q.Speed},
        {"replay", q.Replay ? q.ReplayPath : std::string()},
        {"reachedTarget", g.Reached},
        {"stopReason", g.StopReason},
        {"sessionSeconds", s.Time},
        {"wallSeconds", result.WallSeconds},
        {"realtime", session.Run.Realtime}}},
      {"removedVolumeMm3", s.RemovedTotalMm3},
      {"removedByTissueMm3", removedByTissue},
      {"farthestRemovalFromPathMm", farthest},
      {"servoTickP50Us", result.TickCompute.P50Us},
      {"servoTickP99Us", result.TickCompute.P99Us},
      {"servoTickMaxUs", result.TickCompute.MaxUs},
      {"ticks", result.Ticks},
      {"dirtyBlockRecontourP95Ms", NearestRankPercentile(g.ContourMs, 0.95)},
      {"dirtyBlocksPerFrameMean", g.MeanBlocks},
      {"meshAssembleP95Ms", NearestRankPercentile(g.AssembleMs, 0.95)},
      {"displayFrames", g.ContourMs.size()},
      {"wholeBoneRecontourMs", g.WholeMs},
      {"wholeBoneTriangles", g.WholeTriangles},
      {"peakForceN", g.Peak},
      {"meanCuttingForceN", g.CuttingTicks ? g.CuttingForce / g.CuttingTicks : 0.0},
      {"clampedTicks", g.Clamped},
      {"protected",
       {{"segments", q.Protect},
        {"refusedTicks", s.RefusedTicks},
        {"stopped", s.Stopped},
        {"closestApproachMm", std::isfinite(s.ClosestApproach) ? nlohmann::json(s.ClosestApproach) : nlohmann::json(nullptr)}}}};
  doc["servo"] = ServoJson(result, session.Run);
  if (q.HasPlan) {  // the score keys at the top, as `roboplan score` prints them
    doc.update(ExecutionScoreJson(session.Guided.Score));
    doc["enteredForbidden"] = session.Guided.EnteredForbidden;
    doc["drillSeconds"] = session.Guided.DrillSeconds;
    const TrajectorySnapshot& t = session.Trajectory;
    doc["plan"] = {{"file", q.Plan}, {"trajectory", t.Name}, {"entry", Json(t.Entry)}, {"target", Json(t.Target)},
                   {"toolDiameterMm", t.ToolDiameterMm}};
    nlohmann::json fixtures = nlohmann::json::array();
    for (const FixtureEntry& e : session.Fixtures->Entries)
      fixtures.push_back({{"kind", FixtureKindName(e.Fixture->Kind())}, {"name", e.Fixture->Name()},
                          {"stiffnessNPerMm", e.Tuning.Stiffness}, {"dampingNsPerMm", e.Tuning.Damping},
                          {"captureMm", e.Tuning.Capture}});
    doc["fixtures"] = fixtures;
    doc["hand"] = {{"tremorMm", q.Tremor}, {"driftMmPerS", q.Drift}, {"seed", q.Seed}};
  }
  if (q.Block) {
    bool exact = false;
    const double expected = CapsuleVolumeInBox(q.From, g.Reached ? q.To : s.Proxy, q.Radius, q.BlockLo, q.BlockHi, exact);
    doc["expectedVolumeMm3"] = expected;
    doc["expectedMethod"] = exact ? "analytic: pi r^2 L + 4/3 pi r^3" : "numerical: the capsule inside the block";
    doc["volumeErrorPercent"] = expected > 0 ? 100.0 * (s.RemovedTotalMm3 - expected) / expected : 0.0;
  }
  return doc;
}

// Writes the --model and --picture files; their names go into the report's "outputs".
int WriteDrillOutputs(const DrillRequest& q, const DrillWork& session, nlohmann::json& outputs, std::ostream& err) {
  std::string error;
  if (!q.Record.empty()) outputs["recording"] = q.Record;
  if (q.HasModel) {
    if (!WriteModelFile(q.Model, session.Logic->GetDrilledMesh(), error)) return Fail(err, error);
    outputs["model"] = q.Model;
  }
  if (q.HasPicture) {
    TunnelPicture picture;
    picture.Bone = session.Logic->GetDrilledMesh();
    picture.Volume = session.Logic->GetBone();
    picture.Materials = session.Logic->GetMaterials();
    picture.From = q.From;
    picture.To = q.To;
    picture.Radius = q.Radius;
    for (const DrillRecordLine& l : session.Result.Records) picture.Path.push_back(l.Record.Proxy);
    if (!session.Logic->GetProtectedSurface().Triangles.empty())
      picture.Protected = TriangleMeshToPolyData(session.Logic->GetProtectedSurface());
    if (!WriteTunnelPicture(q.Picture, picture, error)) return Fail(err, error);
    outputs["picture"] = q.Picture;
  }
  return 0;
}

void ReportDrillText(const DrillRequest& q, const DrillWork& session, const DrillFigures& g, const nlohmann::json& doc,
                     std::ostream& out) {
  const DrillState& s = session.Result.Final;
  const DrillRunResult& result = session.Result;
  const DrillBoneReport& built = session.Logic->GetBoneReport();
  const std::vector<Material>& materials = session.Logic->GetMaterials();
  char line[512];
  std::snprintf(line, sizeof line, "bone: %s at %.2f mm, %zu blocks (%.1f MB), built in %.2f s\n",
                q.Block ? "block" : q.Segmentation.c_str(), q.Voxel, built.StoredBlocks, built.MemoryMB, built.Seconds);
  out << line;
  std::snprintf(line, sizeof line, "stroke: %.2f mm with a %.2f mm burr, %s after %.2f s\n", g.Length, q.Radius,
                g.StopReason.c_str(), s.Time);
  out << line;
  std::snprintf(line, sizeof line, "removed: %.2f mm^3", s.RemovedTotalMm3);
  out << line;
  for (size_t m = 0; m < materials.size(); ++m)
    if (s.RemovedMm3[m] > 0) {
      std::snprintf(line, sizeof line, ", %s %.2f", materials[m].Tissue.c_str(), s.RemovedMm3[m]);
      out << line;
    }
  if (q.Block) {
    std::snprintf(line, sizeof line, " (expected %.2f, %+.2f %%)", doc["expectedVolumeMm3"].get<double>(),
                  doc["volumeErrorPercent"].get<double>());
    out << line;
  }
  out << "\n";
  std::snprintf(line, sizeof line, "servo tick: p50 %.1f us, p99 %.1f us over %llu ticks\n", result.TickCompute.P50Us,
                result.TickCompute.P99Us, static_cast<unsigned long long>(result.Ticks));
  out << line;
  out << "servo load: " << MachineLoadSummary(result.Load) << "\n";
  std::snprintf(line, sizeof line,
                "display: %zu frames, dirty-block re-contour p95 %.2f ms (%.1f blocks), mesh assembly p95 %.1f ms, "
                "whole bone %.1f ms\n",
                g.ContourMs.size(), NearestRankPercentile(g.ContourMs, 0.95), g.MeanBlocks,
                NearestRankPercentile(g.AssembleMs, 0.95), g.WholeMs);
  out << line;
  std::snprintf(line, sizeof line, "force: peak %.2f N, clamped %zu ticks\n", g.Peak, g.Clamped);
  out << line;
  if (built.HasProtected) {
    std::snprintf(line, sizeof line, "protected: closest approach %.2f mm, %s\n", s.ClosestApproach,
                  s.Stopped ? "the burr was stopped there" : "not reached");
    out << line;
  }
  if (q.HasPlan) {
    const ExecutionScore& score = session.Guided.Score;
    std::snprintf(line, sizeof line,
                  "against the plan: entry %.2f mm, tip %.2f mm, angle %.2f deg, depth error %+.2f mm, largest deviation "
                  "%.2f mm; %s a forbidden region\n",
                  score.EntryOffsetMm, score.TipOffsetMm, score.AngleDeg, score.DepthErrorMm, score.MaxDeviationMm,
                  session.Guided.EnteredForbidden ? "ENTERED" : "never entered");
    out << line;
  }
}

}  // namespace

int RunDrillCommand(const std::vector<std::string>& args, vtkRPScene* sceneIn, std::ostream& out, std::ostream& err) {
  DrillRequest request;
  if (const auto exitCode = ParseDrillRequest(args, out, err, request)) return *exitCode;
  TerminalProgress progress("drill", request.Json, err);
  vtkNew<vtkRPScene> ownScene;
  DrillWork session;
  if (const int code = RunDrillSession(request, session, sceneIn ? sceneIn : ownScene.GetPointer(), progress, err)) return code;
  const DrillFigures figures = MeasureDrill(request, session);
  nlohmann::json doc = DrillJson(request, session, figures);
  nlohmann::json outputs = nlohmann::json::object();
  if (const int code = WriteDrillOutputs(request, session, outputs, err)) return code;
  doc["outputs"] = outputs;
  progress.Report(1.0, "done");
  if (request.Json)
    out << doc.dump(2) << "\n";
  else
    ReportDrillText(request, session, figures, doc, out);
  return 0;
}

}  // namespace rp
