#include "rpHapticsCommand.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <thread>

#include <nlohmann/json.hpp>
#include <vtkNew.h>

#include "rpArgParser.h"
#include "rpDeviceProfiles.h"
#include "rpFormat.h"
#include "rpPolyDataTriangleMesh.h"
#include "rpProgress.h"
#include "rpSceneIO.h"
#include "rpServoLoadReport.h"
#include "rpSimulatedDevice.h"
#include "vtkRPHapticsLogic.h"
#include "vtkRPModelNode.h"
#include "vtkRPScene.h"

namespace rp {
namespace {

// An analytic demo scene when no --scene is given: a bone "condyle" and a fat pad beside it.
void AddDemoModels(vtkRPScene* scene) {
  struct Item {
    const char* Name;
    const char* Tissue;
    rp::TriangleMesh Mesh;
  };
  const Item items[] = {{"Femur condyle", "bone", rp::shapes::Sphere({-35, 0, 0}, 20, 5)},
                        {"Fat pad", "fat", rp::shapes::Box({10, -25, -20}, {60, 25, 0})}};
  for (const Item& item : items) {
    vtkNew<vtkRPModelNode> model;
    model->SetName(item.Name);
    model->SetTissueClass(item.Tissue);
    model->SetHaptic(true);
    model->SetPolyData(rp::TriangleMeshToPolyData(item.Mesh));
    scene->AddNode(model);
  }
}

// Scripted explorations over the scene's haptic surfaces (RAS), found by casting rays down.
std::shared_ptr<rp::WaypointTrajectory> MakeTrajectory(const std::string& name, const rp::HapticScene& scene,
                                                       std::string& error) {
  rp::Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const rp::Vec3& p : scene.Mesh.Points) {
    lo = rp::Min(lo, p);
    hi = rp::Max(hi, p);
  }
  const double above = hi.z + 10;
  auto surfaceZ = [&](double x, double y, double& z) {
    rp::SegmentHit hit;
    if (!scene.Tree.FirstHit({x, y, above}, {x, y, lo.z - 1}, rp::BVH::Faces::FrontOnly, hit)) return false;
    z = hit.Point.z;
    return true;
  };
  std::vector<double> t;
  std::vector<rp::Vec3> p;
  double now = 0;
  auto go = [&](const rp::Vec3& q, double speed) {
    if (!p.empty()) now += std::fmax(1e-3, rp::Norm(q - p.back()) / speed);
    t.push_back(now);
    p.push_back(q);
  };
  const rp::Vec3 center = (lo + hi) * 0.5;
  if (name == "probe") {
    // Press 2 mm into the surface on a 5 x 3 grid, at 50 mm/s in and out.
    go({center.x, center.y, above}, 100);
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 5; ++i) {
        const double x = lo.x + (hi.x - lo.x) * (i + 0.5) / 5, y = lo.y + (hi.y - lo.y) * (j + 0.5) / 3;
        double z;
        if (!surfaceZ(x, y, z)) continue;
        go({x, y, z + 5}, 150);
        go({x, y, z - 2}, 50);
        go({x, y, z - 2.0001}, 1e-3 / 0.2);  // hold 0.2 s
        go({x, y, z + 5}, 50);
      }
  } else if (name == "sweep") {
    // 1.5 mm below the lowest surface met along the centre row, sweep across everything at
    // 100 mm/s: the proxy slides over tops and edges of the higher models.
    double z = HUGE_VAL;
    for (int i = 0; i <= 40; ++i) {
      double zi;
      if (surfaceZ(lo.x + (hi.x - lo.x) * i / 40, center.y, zi)) z = std::fmin(z, zi);
    }
    if (!std::isfinite(z)) z = hi.z;
    go({lo.x - 5, center.y, above}, 100);
    go({lo.x - 5, center.y, z - 1.5}, 100);
    go({hi.x + 5, center.y, z - 1.5}, 100);
    go({hi.x + 5, center.y - (hi.y - lo.y) / 4, z - 1.5}, 100);
    go({lo.x - 5, center.y - (hi.y - lo.y) / 4, z - 1.5}, 100);
    go({lo.x - 5, center.y, above}, 100);
  } else {
    auto path = std::make_shared<rp::WaypointTrajectory>();
    if (!path->LoadCSV(name, error)) return nullptr;
    return path;
  }
  if (p.size() < 2) {
    error = "trajectory '" + name + "': no haptic surface below the scene's bounding box";
    return nullptr;
  }
  auto path = std::make_shared<rp::WaypointTrajectory>();
  if (!path->Set(t, p, error)) return nullptr;
  return path;
}

nlohmann::json StatsJson(const rp::TimingStats& s) {
  return {{"count", s.Count}, {"meanUs", s.MeanUs}, {"p50Us", s.P50Us}, {"p99Us", s.P99Us},
          {"p999Us", s.P999Us}, {"maxUs", s.MaxUs}};
}

// What `roboplan haptics` was asked to do, read from its options (types and ranges checked by the parser).
struct HapticsRequest {
  double Seconds = -1, Rate = 1000, Spin = 100;
  long ToolPoints = 1, Cpu = -1;
  bool Shield = false;
  bool Json = false;
  std::string ScenePath, Trajectory, MaterialsPath, LogPath;
  DeviceProfile Profile;
};

void DeclareHapticsOptions(rp::ArgParser& parser) {
  parser.Option("scene", "file.rpscene", "scene with model nodes flagged haptic (default: an analytic demo)")
      .Input(FileKind::Any, {SceneFileExtension})
      .Option("seconds", "N", "how long to run (default: the trajectory's duration)")
      .Number()
      .GreaterThan(0)
      .AtMost(3600)
      .Option("trajectory", "probe|sweep|file.csv", "scripted motion; CSV rows t,x,y,z in RAS (s, mm)", "probe")
      .Option("device", DeviceProfileKeys(), "simulated device profile (its force and stiffness limits)",
              DeviceProfiles().front().Key)
      .OneOf()
      .Option("materials", "file.json", "tissue material table (default: Resources/Materials/materials.json)")
      .Input(FileKind::Any, {".json"})
      .Option("tool-points", "n", "points along the shaft (tip + n-1 every 10 mm)", "1")
      .Integer()
      .AtLeast(1)
      .AtMost(MaxToolPoints)
      .Option("log", "file.csv", "write the session log (time, HIP, proxy, force, tissue, tick time)")
      .Output(FileKind::Any, {".csv"})
      .Option("rate", "Hz", "servo rate", "1000")
      .Number()
      .AtLeast(1)
      .AtMost(100000)
      .Option("spin", "us", "busy-wait this long before each deadline (smaller jitter, more CPU)", "100")
      .Number()
      .AtLeast(0)
      .Option("cpu", "N", "pin the servo thread to CPU N and move the process's other threads off it (-1: not pinned)",
              "-1")
      .Integer()
      .AtLeast(-1)
      .AtMost(1023)
      .Flag("shield", "with --cpu: also keep every other process's threads off that CPU while the servo runs "
                      "(as `cset shield` does; needs root for other users' processes)");
}

// Options -> request; 0 when they make a request, else the exit code (reason on `err`).
int ReadHapticsRequest(const rp::ArgParser& parser, HapticsRequest& request, std::ostream& err) {
  try {
    if (parser.Has("seconds")) request.Seconds = parser.GetDouble("seconds");
    request.Rate = parser.GetDouble("rate");
    request.Spin = parser.GetDouble("spin");
    request.ToolPoints = parser.GetInt("tool-points");
    request.Cpu = parser.GetInt("cpu");
    request.Shield = parser.Has("shield");
  } catch (const std::exception& e) {
    err << "roboplan haptics: " << e.what() << "\n";
    return 2;
  }
  // Types and ranges were checked by the parser (declared above); the spin depends on the rate.
  if (!(request.Spin < 1e6 / request.Rate)) {
    err << "roboplan haptics: --spin must be shorter than the servo period (" << 1e6 / request.Rate << " us)\n";
    return 2;
  }
  if (request.Shield && request.Cpu < 0) {
    err << "roboplan haptics: --shield needs --cpu N (the CPU to keep the other processes off)\n";
    return 2;
  }
  std::string error;
  if (!FindDeviceProfile(parser.Get("device"), request.Profile, error)) {
    err << "roboplan haptics: " << error << "\n";
    return 2;
  }
  request.Json = parser.Json();
  if (parser.Has("scene")) request.ScenePath = parser.Get("scene");
  request.Trajectory = parser.Get("trajectory");
  request.MaterialsPath = parser.Get("materials");
  request.LogPath = parser.Get("log");
  return 0;
}

// The given scene file, or the analytic demo scene when none is given; false (reason on `err`) on failure.
bool FillHapticsScene(vtkRPScene* scene, const HapticsRequest& request, std::ostream& err) {
  if (request.ScenePath.empty()) {
    AddDemoModels(scene);
    return true;
  }
  const rp::SceneLoadReport report = rp::LoadScene(scene, request.ScenePath);
  if (!report.Ok) {
    err << "roboplan haptics: " << report.Error << "\n";
    return false;
  }
  for (const auto& problem : report.Problems) err << "roboplan haptics: warning: " << problem << "\n";
  return true;
}

// The logic's session as the request asks: device, materials, the scripted motion over the
// scene's haptic surfaces (RAS), tool points, log, loop; 0 or the exit code.
int PrepareHapticsRun(vtkRPHapticsLogic* logic, HapticsRequest& request, std::ostream& err) {
  std::string error;
  if (!logic->SetDeviceProfile(request.Profile.Key, error)) {
    err << "roboplan haptics: " << error << "\n";
    return 2;
  }
  logic->SetMaterialsPath(request.MaterialsPath);
  auto preview = logic->PreviewHapticScene(error);
  if (!preview) {
    err << "roboplan haptics: " << error << "\n";
    return 1;
  }
  if (preview->Tree.Empty()) {
    err << "roboplan haptics: the scene has no haptic models (model nodes with Haptic on and polygons)\n";
    return 1;
  }
  auto path = MakeTrajectory(request.Trajectory, *preview, error);
  if (!path) {
    err << "roboplan haptics: " << error << "\n";
    return request.Trajectory == "probe" || request.Trajectory == "sweep" ? 1 : 2;
  }
  if (request.Seconds < 0) request.Seconds = std::fmin(path->Duration() + 0.1, 600.0);
  logic->SetSimulatedTrajectory(path);  // in RAS, as the servo takes the simulated stylus
  std::vector<rp::Vec3> points{rp::Vec3{}};
  for (long i = 1; i < request.ToolPoints; ++i) points.push_back({0, 0, 10.0 * i});
  logic->SetToolPoints(points);
  logic->SetLogPath(request.LogPath);
  rp::ServoLoop::Options loop;
  loop.RateHz = request.Rate;
  loop.SpinUs = request.Spin;
  loop.CpuAffinity = static_cast<int>(request.Cpu);
  loop.ShieldCpu = request.Shield;
  logic->SetLoopOptions(loop);
  logic->SetRampSeconds(0.2);
  logic->SetSummarize(true);
  return 0;
}

// Runs the logic's session for the request's seconds, printing new warnings and progress.
bool RunHapticsSession(vtkRPHapticsLogic* logic, const HapticsRequest& request, std::ostream& err) {
  rp::TerminalProgress progress("haptics", request.Json, err);
  size_t warned = 0;
  auto printWarnings = [&] {
    const rp::HapticSession* session = logic->GetSession();
    for (; session && warned < session->Warnings().size(); ++warned)
      err << "roboplan haptics: warning: " << session->Warnings()[warned] << "\n";
  };
  std::string error;
  const bool ran = logic->RunSimulated(request.Seconds, [&](double elapsed) {
    printWarnings();  // e.g. a tissue clamped once the measured servo period is known
    progress.Report(std::floor(10 * std::fmin(1.0, elapsed / request.Seconds)) / 10, "exploring");
  }, error);
  printWarnings();
  if (!ran) err << "roboplan haptics: " << error << "\n";
  return ran;
}

// What the finished run measured, read once after Stop.
struct HapticsOutcome {
  const HapticsRequest& Request;
  rp::HapticSession& Session;
  const rp::HapticForceSummary& Stats;
  rp::ServoStats Servo;
  rp::HapticState Last;
  std::string TissueName(int label) const {
    const auto& names = Session.TissueNames();
    return label >= 0 && static_cast<size_t>(label) < names.size() ? names[static_cast<size_t>(label)] : std::string("?");
  }
};

void ReportHapticsJson(const HapticsOutcome& o, std::ostream& out) {
  const HapticsRequest& request = o.Request;
  const rp::HapticSession& session = o.Session;
  const rp::HapticForceSummary& stats = o.Stats;
  const rp::ServoStats& servo = o.Servo;
  nlohmann::json tissues = nlohmann::json::object();
  for (const auto& [label, ticks] : stats.TissueTicks) tissues[o.TissueName(label)] = ticks;
  nlohmann::json clamps = nlohmann::json::array();
  for (const MaterialClamp& c : session.Clamps())
    clamps.push_back({{"tissue", c.Tissue},
                      {"requestedStiffness", c.RequestedStiffness},
                      {"renderedStiffness", c.RenderedStiffness},
                      {"requestedDamping", c.RequestedDamping},
                      {"renderedDamping", c.RenderedDamping},
                      {"clamped", c.Clamped()},
                      {"limit", c.Limit}});
  nlohmann::json doc = {
      {"seconds", request.Seconds},
      {"rateHz", request.Rate},
      {"trajectory", request.Trajectory},
      {"device",
       {{"profile", request.Profile.Key},
        {"name", request.Profile.Info.Name},
        {"maxForceN", request.Profile.Info.MaxForce},
        {"nominalMaxStiffness", request.Profile.Info.NominalMaxStiffness}}},
      {"materials", {{"source", session.Materials().Source()}, {"stabilityPeriodS", session.StabilityPeriod()},
                     {"tissues", clamps}}},
      {"scene", {{"triangles", session.SceneTriangles()}, {"warnings", session.Warnings()}}},
      {"servo",
       {{"ticks", servo.Ticks},
        {"realTimePriority", servo.RealTimePriority},
        {"priorityNote", session.Scheduler().PriorityNote()},
        {"period", StatsJson(servo.Period)},
        {"compute", StatsJson(servo.Compute)},
        {"lateness", StatsJson(servo.Lateness)},
        {"missedDeadlines", servo.MissedDeadlines},
        {"missedPercent", servo.MissedPercent()},
        {"missedBudgetPercent", ServoStats::MissedBudgetPercent},
        {"overruns", servo.Overruns},
        {"stalls", o.Last.Stalls},
        {"watchdogTrips", o.Last.WatchdogTrips},
        {"load", MachineLoadJson(session.Scheduler().Load())},
        {"missesReading", MachineLoadReading(session.Scheduler().Load(), servo.MissedDeadlines, servo.Overruns)}}},
      {"force",
       {{"maxN", stats.MaxForce},
        {"meanInContactN", stats.MeanForceInContact()},
        {"contactFraction", stats.ContactFraction()},
        {"clampedTicks", stats.ClampedTicks},
        {"stallLimitedTicks", stats.StallLimitedTicks},
        {"tissueTicks", tissues}}},
      {"log", {{"path", request.LogPath}, {"records", stats.Records}, {"dropped", o.Session.Servo().LogRing().DroppedCount()}}}};
  out << doc.dump(2) << "\n";
}

void ReportHapticsText(const HapticsOutcome& o, std::ostream& out) {
  const HapticsRequest& request = o.Request;
  const DeviceProfile& profile = request.Profile;
  const rp::HapticSession& session = o.Session;
  const rp::HapticForceSummary& stats = o.Stats;
  const rp::ServoStats& servo = o.Servo;
  out << Format("device: %s (%.1f N peak, %.2f N/mm nominal maximum stiffness)\n", profile.Info.Name.c_str(),
                profile.Info.MaxForce, profile.Info.NominalMaxStiffness);
  out << Format("materials: %s; stiffness requested -> rendered at a %.2f ms servo period:\n",
                session.Materials().Source().c_str(), 1e3 * session.StabilityPeriod());
  for (const MaterialClamp& c : session.Clamps())
    out << Format("  %-10s %.2f -> %.2f N/mm%s\n", c.Tissue.c_str(), c.RequestedStiffness, c.RenderedStiffness,
                  c.Clamped() ? "  CLAMPED" : "");
  out << Format("scene: %zu haptic triangles; trajectory %s, %.1f s\n", session.SceneTriangles(),
                request.Trajectory.c_str(), request.Seconds);
  out << Format("servo: %llu ticks at %.0f Hz (%s)\n", static_cast<unsigned long long>(servo.Ticks), request.Rate,
                session.Scheduler().PriorityNote().c_str());
  out << Format("  period  p50 %.1f us  p99 %.1f us  max %.1f us  missed deadlines %llu (%.2f %%, budget %.1f %%)  "
                "overruns %llu  stalls %u\n",
                servo.Period.P50Us, servo.Period.P99Us, servo.Period.MaxUs,
                static_cast<unsigned long long>(servo.MissedDeadlines), servo.MissedPercent(), ServoStats::MissedBudgetPercent,
                static_cast<unsigned long long>(servo.Overruns), o.Last.Stalls);
  out << Format("  compute p50 %.2f us  p99 %.2f us  max %.1f us  watchdog trips %u\n", servo.Compute.P50Us,
                servo.Compute.P99Us, servo.Compute.MaxUs, o.Last.WatchdogTrips);
  out << "  load: " << MachineLoadSummary(session.Scheduler().Load()) << "\n";
  out << "  misses: " << MachineLoadReading(session.Scheduler().Load(), servo.MissedDeadlines, servo.Overruns) << "\n";
  out << Format("force: max %.3f N, mean in contact %.3f N, contact %.1f%% of ticks, clamped %llu ticks\n",
                stats.MaxForce, stats.MeanForceInContact(), 100 * stats.ContactFraction(),
                static_cast<unsigned long long>(stats.ClampedTicks));
  for (const auto& [label, ticks] : stats.TissueTicks)
    out << Format("  %-10s %llu ticks in contact\n", o.TissueName(label).c_str(), static_cast<unsigned long long>(ticks));
  if (!request.LogPath.empty())
    out << Format("log: %s (%llu records)\n", request.LogPath.c_str(), static_cast<unsigned long long>(stats.Records));
}

}  // namespace

int RunHapticsCommand(const std::vector<std::string>& arguments, vtkRPScene* sceneIn, std::ostream& out,
                      std::ostream& err) {
  rp::ArgParser parser("haptics",
                       "Touch the scene's haptic models with the simulated device along a scripted trajectory at "
                       "1 kHz; prints servo timing, force statistics and the tissues the device clamps.");
  DeclareHapticsOptions(parser);
  if (const auto exitCode = parser.ParseCommand(arguments, out, err)) return *exitCode;
  HapticsRequest request;
  if (const int exitCode = ReadHapticsRequest(parser, request, err)) return exitCode;

  vtkNew<vtkRPScene> ownScene;
  vtkRPScene* scene = sceneIn ? sceneIn : ownScene.GetPointer();
  if (!FillHapticsScene(scene, request, err)) return 1;
  vtkNew<vtkRPHapticsLogic> logic;
  logic->SetScene(scene);
  if (const int exitCode = PrepareHapticsRun(logic, request, err)) return exitCode;
  if (!RunHapticsSession(logic, request, err)) return 1;

  rp::HapticSession& session = *logic->GetSession();
  HapticsOutcome outcome{request, session, session.Summary(), session.Scheduler().Stats(), {}};
  session.Servo().ReadState(outcome.Last);
  if (request.Json)
    ReportHapticsJson(outcome, out);
  else
    ReportHapticsText(outcome, out);
  return 0;
}

}  // namespace rp
