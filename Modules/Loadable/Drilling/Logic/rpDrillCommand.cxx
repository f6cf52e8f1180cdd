#include "rpDrillCommand.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include <nlohmann/json.hpp>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkDataArray.h>
#include <vtkPolyData.h>

#include "rpArgParser.h"
#include "rpDrillAnalytic.h"
#include "rpDrillBoneBuilder.h"
#include "rpDrillRun.h"
#include "rpHapticSceneBridge.h"
#include "rpModelIO.h"
#include "rpSegmentationIO.h"
#include "rpServoLoadReport.h"
#include "rpSimulatedDevice.h"
#include "rpTunnelPicture.h"
#include "rpBlockMesher.h"
#include "rpVolumeFiles.h"
#include "rpVolumeIO.h"
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

// Resolves segment references (ID, name or label value) against a segmentation.
bool FindSegments(vtkRPSegmentationNode* segmentation, const std::vector<std::string>& refs, std::vector<int>& labels,
                  std::vector<std::string>& tissues, std::vector<std::string>& names, std::string& error) {
  for (const std::string& ref : refs) {
    const vtkRPSegmentationNode::Segment* found = segmentation->GetSegmentByID(ref);
    for (int n = 0; !found && n < segmentation->GetNumberOfSegments(); ++n) {
      const auto& s = segmentation->GetNthSegment(n);
      if (s.Name.size() == ref.size() && std::equal(ref.begin(), ref.end(), s.Name.begin(), [](char a, char b) {
            return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b));
          }))
        found = &s;
    }
    if (!found && !ref.empty() && ref.find_first_not_of("0123456789") == std::string::npos)
      found = segmentation->GetSegmentByLabel(std::stoi(ref));
    if (!found) {
      error = "no segment '" + ref + "' in the segmentation (segments:";
      for (int n = 0; n < segmentation->GetNumberOfSegments(); ++n) error += " " + segmentation->GetNthSegment(n).ID;
      error += ")";
      return false;
    }
    labels.push_back(found->LabelValue);
    tissues.push_back(found->TissueClass);
    names.push_back(found->ID);
  }
  return true;
}

// Reads a .seg.nrrd, or any labelmap volume (segments are then label values).
bool ReadLabels(const std::string& path, vtkRPSegmentationNode* segmentation, std::string& error) {
  std::string segError;
  if (ReadSegmentationFile(path, segmentation, segError) && segmentation->GetNumberOfSegments() > 0) return true;
  if (!ReadVolumeFile(path, segmentation, error)) {
    error = "cannot read the segmentation '" + path + "': " + (segError.empty() ? error : segError);
    return false;
  }
  // A plain labelmap: one segment per label value found.
  vtkImageData* image = segmentation->GetImageData();
  std::vector<long long> values;
  for (vtkIdType i = 0; i < image->GetNumberOfPoints(); ++i) {
    const long long v = static_cast<long long>(image->GetPointData()->GetScalars()->GetTuple1(i));
    if (v != 0 && std::find(values.begin(), values.end(), v) == values.end()) {
      values.push_back(v);
      if (values.size() > 255) break;
    }
  }
  for (long long v : values) {
    vtkRPSegmentationNode::Segment s;
    s.ID = std::to_string(v);
    s.Name = "Label " + s.ID;
    s.LabelValue = static_cast<int>(v);
    segmentation->SetSegment(s);
  }
  return true;
}

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

}  // namespace

int RunDrillCommand(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  ArgParser parser("drill",
                   "Drill a straight stroke into a bone with a spherical burr at the servo rate (simulated device): removed "
                   "volume per tissue, forces, servo and display timings.");
  parser.Positional("segmentation", "bone segmentation (.seg.nrrd, or a labelmap volume)", false)
      .Flag("block", "drill an analytic block of bone instead (known volume of the stroke)")
      .Option("segment", "ID", "bone segment to drill: ID, name or label value (repeatable)")
      .Option("protect", "ID", "protected segment: the burr stops when it reaches it (repeatable)")
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
      .Option("timeout", "S", "give up after this much session time (default: three times the stroke at the feed rate + 5 s)")
      .Option("record", "FILE", "write the drill path (time, burr, proxy, force, removed volume per tick)")
      .Option("replay", "FILE", "drive the burr along a recorded drill path instead of --from/--to")
      .Option("model", "FILE", "write the drilled bone's surface (" + ModelFileExtensionsText() + ")")
      .Option("picture", "FILE.png", "render a picture of the tunnel (needs a display or Xvfb)")
      .Option("cpu", "N", "--realtime: pin the servo thread to CPU N and move the other threads off it (-1: not pinned)", "-1")
      .Flag("realtime", "run the 1 kHz servo thread and the 30 Hz display thread on the wall clock (default: the same "
                        "ticks scripted on one thread, as fast as the CPU allows)");
  if (const auto exitCode = parser.ParseCommand(args, out, err)) return *exitCode;
  const bool json = parser.Json();
  const bool replay = parser.Has("replay");
  int cpu = -1;
  double radius = 0, speed = 0, voxel = 0.3, rpm = 60000, feed = 2, shell = 0, margin = 0, timeout = -1;
  Vec3 from, to, blockLo{-20, -20, -20}, blockHi{20, 20, 20};
  try {
    voxel = parser.GetDouble("voxel");
    cpu = static_cast<int>(parser.GetDouble("cpu"));
    rpm = parser.GetDouble("rpm");
    feed = parser.GetDouble("feed");
    shell = parser.GetDouble("shell");
    margin = parser.GetDouble("margin");
    if (parser.Has("timeout")) timeout = parser.GetDouble("timeout");
    const auto bounds = parser.GetDoubles("block-bounds", 6);
    blockLo = {bounds[0], bounds[1], bounds[2]};
    blockHi = {bounds[3], bounds[4], bounds[5]};
    if (!replay) {
      for (const char* required : {"burr-radius", "from", "to", "speed"})
        if (!parser.Has(required)) throw std::invalid_argument(std::string("--") + required + " is required (or --replay)");
      radius = parser.GetDouble("burr-radius");
      speed = parser.GetDouble("speed");
      from = ToVec3(parser.GetDoubles("from", 3));
      to = ToVec3(parser.GetDoubles("to", 3));
    }
  } catch (const std::exception& e) {
    err << "roboplan drill: " << e.what() << "\n";
    return 2;
  }
  const bool block = parser.Has("block");
  if (block == parser.Has("segmentation")) {
    err << "roboplan drill: give either --block or a segmentation file (with --segment)\n";
    return 2;
  }
  if (!block && !parser.Has("segment")) {
    err << "roboplan drill: --segment ID is required with a segmentation\n";
    return 2;
  }
  if (!(voxel >= 0.05 && voxel <= 5)) {
    err << "roboplan drill: --voxel must be in [0.05, 5] mm\n";
    return 2;
  }
  if (!replay && !(radius >= 0.25 && radius <= 10)) {
    err << "roboplan drill: --burr-radius must be in [0.25, 10] mm\n";
    return 2;
  }
  if (!replay && !(speed > 0 && speed <= 2000)) {
    err << "roboplan drill: --speed must be in (0, 2000] mm/s\n";
    return 2;
  }
  if (!(rpm >= 0 && rpm <= 200000) || !(feed > 0 && feed <= 1000) || shell < 0 || margin < 0) {
    err << "roboplan drill: --rpm must be in [0, 200000], --feed positive, --shell and --margin not negative\n";
    return 2;
  }
  if (block && !(blockLo.x < blockHi.x && blockLo.y < blockHi.y && blockLo.z < blockHi.z)) {
    err << "roboplan drill: --block-bounds must give a box with R0 < R1, A0 < A1, S0 < S1\n";
    return 2;
  }
  TerminalProgress progress("drill", json);
  std::string error;

  // ---- the recorded path, when replaying
  DrillRecording recording;
  if (replay) {
    if (!DrillRecording::Read(parser.Get("replay"), recording, error)) {
      err << "roboplan drill: " << error << "\n";
      return 1;
    }
    from = recording.Lines.front().Record.Hip;
    to = recording.Lines.back().Record.Hip;
    radius = recording.Lines.front().Record.Radius;
    if (recording.Info.Voxel > 0 && !parser.Has("voxel")) voxel = recording.Info.Voxel;
    if (recording.Info.FeedRate > 0 && !parser.Has("feed")) feed = recording.Info.FeedRate;
  }

  // ---- materials and the voxel bone
  MaterialTable table;
  if (!LoadMaterialTable(table, error, parser.Get("materials"))) {
    err << "roboplan drill: " << error << "\n";
    return 1;
  }
  const std::vector<Material> materials = DrillableMaterials(table);
  if (materials.empty()) {
    err << "roboplan drill: " << table.Source() << " has no drillable material (no \"hardness\")\n";
    return 1;
  }
  auto bone = std::make_unique<DrillVolume>();
  auto protectedSurface = std::make_unique<DrillVolume>();
  DrillBoneReport built;
  std::vector<std::string> boneNames;
  const auto buildStart = std::chrono::steady_clock::now();
  if (block) {
    const uint8_t cortical = FindDrillMaterial(materials, "bone") ? FindDrillMaterial(materials, "bone") : 1;
    const uint8_t trabecular = FindDrillMaterial(materials, "trabecular bone");
    if (shell > 0 && trabecular == 0) {
      err << "roboplan drill: --shell needs a drillable \"trabecular bone\" in the material table\n";
      return 1;
    }
    if (!BuildAnalyticBone(BlockBone(blockLo, blockHi, cortical, shell, trabecular), voxel, materials, *bone, error)) {
      err << "roboplan drill: " << error << "\n";
      return 1;
    }
    built.GridVoxels = bone->Grid().VoxelCount();
    built.StoredBlocks = bone->AllocatedBlocks();
    built.MemoryMB = bone->MemoryBytes() / 1e6;
    built.VolumeMm3 = bone->OriginalVolumes();
    built.Seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - buildStart).count();
    boneNames = {"block"};
  } else {
    vtkNew<vtkRPSegmentationNode> segmentation;
    if (!ReadLabels(parser.Get("segmentation"), segmentation, error)) {
      err << "roboplan drill: " << error << "\n";
      return 1;
    }
    DrillBoneSource source;
    source.Labels = FromNode(segmentation);
    std::vector<std::string> protectedNames;
    if (!FindSegments(segmentation, parser.GetAll("segment"), source.BoneLabels, source.BoneTissues, boneNames, error) ||
        !FindSegments(segmentation, parser.GetAll("protect"), source.ProtectedLabels, source.ProtectedTissues,
                      protectedNames, error)) {
      err << "roboplan drill: " << error << "\n";
      return 1;
    }
    if (parser.Has("ct") && !ReadVolume(parser.Get("ct"), source.CT, error)) {
      err << "roboplan drill: the CT: " << error << "\n";
      return 1;
    }
    source.Spacing = voxel;
    if (margin > 0) {
      const Vec3 pad{margin + radius, margin + radius, margin + radius};
      source.HasRegion = true;
      source.RegionLo = Min(from, to) - pad;
      source.RegionHi = Max(from, to) + pad;
    }
    if (!BuildDrillBone(source, materials, *bone, protectedSurface.get(), built, error,
                        [&](double f, const std::string& m) { progress.Report(0.3 * f, "voxel bone: " + m); })) {
      err << "roboplan drill: " << error << "\n";
      return 1;
    }
  }

  // ---- the protected structure's surface (distance read-out)
  TriangleMesh protectedMesh;
  BVH protectedTree;
  if (built.HasProtected) {
    BlockMesher mesher(*protectedSurface);
    mesher.ContourAll();
    for (const BlockMesh& b : mesher.Blocks()) {
      const int32_t base = static_cast<int32_t>(protectedMesh.Points.size());
      for (size_t p = 0; p < b.Points.size(); p += 3) protectedMesh.Points.push_back({b.Points[p], b.Points[p + 1], b.Points[p + 2]});
      for (size_t t = 0; t < b.Triangles.size(); t += 3)
        protectedMesh.Triangles.push_back({base + int32_t(b.Triangles[t]), base + int32_t(b.Triangles[t + 1]),
                                           base + int32_t(b.Triangles[t + 2])});
    }
    protectedTree.Build(protectedMesh);
  }

  // ---- the device, the servo, the display
  auto path = std::make_shared<WaypointTrajectory>();
  DrillControl on{true, radius, rpm};
  std::function<DrillControl(double)> schedule = [on](double) { return on; };
  if (replay) {
    std::vector<double> times;
    std::vector<Vec3> points;
    for (const DrillRecordLine& l : recording.Lines) {
      times.push_back(l.Record.Time);
      points.push_back(l.Record.Hip);
    }
    if (!path->Set(times, points, error)) {
      err << "roboplan drill: " << parser.Get("replay") << ": " << error << "\n";
      return 1;
    }
    const auto* lines = &recording.Lines;
    schedule = [lines](double t) {
      auto it = std::upper_bound(lines->begin(), lines->end(), t,
                                 [](double time, const DrillRecordLine& l) { return time < l.Record.Time; });
      const DrillRecordLine& l = it == lines->begin() ? lines->front() : *(it - 1);
      return DrillControl{(l.Record.Flags & DrillRecordFlags::BurrOn) != 0, l.Record.Radius, l.Rpm};
    };
  } else {
    path->Set({0.0, 1e-3, 1e-3 + std::max(Norm(to - from), 1e-6) / speed}, {from, from, to}, error);
  }
  SimulatedDevice device;
  device.SetTrajectory(path);
  DrillServoOptions servoOptions;
  servoOptions.FeedRate = feed;
  servoOptions.RampSeconds = 0;  // the burr starts in the bone: no force ramp to hide a jump
  auto servo = std::make_unique<DrillServo>(device, *bone, servoOptions);
  if (built.HasProtected) servo->SetProtectedSurface(&protectedTree);
  DrillControl start = replay ? schedule(0) : on;
  if (replay && !recording.Info.StartCut) start.BurrOn = false;  // a session that began outside the bone
  servo->PlaceBurr(from, start);
  DrillDisplay display(*bone);
  vtkSmartPointer<vtkPolyData> mesh = display.Initialize();

  DrillRunOptions run;
  run.Realtime = parser.Has("realtime");
  run.Schedule = schedule;
  const double length = Norm(to - from);
  const double tolerance = std::max(0.01, 0.05 * voxel);
  if (replay) {
    run.MaxSeconds = recording.Lines.back().Record.Time + 1e-3;
  } else {
    run.MaxSeconds = timeout > 0 ? timeout : 3.0 * length / std::min(speed, feed) + 5.0;
    run.Finished = [to, tolerance](const DrillState& s) { return Norm(s.Proxy - to) < tolerance || s.Stopped; };
  }
  run.RecordPath = parser.Get("record");
  run.RecordInfo = {voxel, feed, servoOptions.ReferenceRpm, replay ? recording.Info.StartCut : true};
  run.OnMesh = [&mesh](vtkPolyData* m) { mesh = m; };
  run.Progress = [&](double f, const std::string& m) { progress.Report(0.3 + 0.65 * f, m); };
  run.Loop.RequestRealTimePriority = run.Realtime;
  run.Loop.CpuAffinity = cpu;
  DrillRunResult result;
  if (!RunDrill(*servo, display, run, result, error)) {
    err << "roboplan drill: " << error << "\n";
    return 1;
  }
  progress.Report(0.97, "measuring");

  // ---- figures
  const DrillState& s = result.Final;
  const bool reached = Norm(s.Proxy - to) < tolerance;
  const std::string stopReason = replay ? "replayed" : reached ? "reached" : (s.Stopped ? "protected" : "timeout");
  std::vector<double> contourMs, blocks, assembleMs;
  for (const DisplayFrame& f : result.Frames) {
    contourMs.push_back(f.ContourMs);
    blocks.push_back(double(f.Blocks));
    assembleMs.push_back(f.AssembleMs);
  }
  double meanBlocks = 0;
  for (double b : blocks) meanBlocks += b / std::max<size_t>(1, blocks.size());
  // The whole bone contoured from scratch, once, for comparison (same code, every block).
  BlockMesher whole(*bone);
  const auto wholeStart = std::chrono::steady_clock::now();
  whole.ContourAll();
  const double wholeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wholeStart).count();
  double peak = 0, cuttingForce = 0;
  size_t clamped = 0, cuttingTicks = 0;
  for (const DrillRecordLine& l : result.Records) {
    const double f = Norm(l.Record.Force);
    peak = std::max(peak, f);
    clamped += (l.Record.Flags & DrillRecordFlags::Clamped) != 0;
    if (l.Record.Flags & DrillRecordFlags::Cutting) cuttingForce += f, ++cuttingTicks;
  }
  nlohmann::json removedByTissue = nlohmann::json::object(), volumeByTissue = nlohmann::json::object();
  for (size_t m = 0; m < materials.size(); ++m) {
    removedByTissue[materials[m].Tissue] = s.RemovedMm3[m];
    volumeByTissue[materials[m].Tissue] = m < built.VolumeMm3.size() ? built.VolumeMm3[m] : 0.0;
  }
  const double farthest = FarthestChangeFromPath(*bone, {from, to});
  nlohmann::json doc = {
      {"bone",
       {{"source", block ? std::string("block") : parser.Get("segmentation")},
        {"segments", boneNames},
        {"voxelMm", voxel},
        {"gridVoxels", built.GridVoxels},
        {"storedBlocks", built.StoredBlocks},
        {"memoryMB", built.MemoryMB},
        {"buildSeconds", built.Seconds},
        {"volumeMm3", volumeByTissue},
        {"materialsFromCT", built.UsedCT}}},
      {"burr", {{"radiusMm", radius}, {"rpm", rpm}, {"feedRateMmPerS", feed}}},
      {"stroke",
       {{"from", Json(from)},
        {"to", Json(to)},
        {"lengthMm", length},
        {"speedMmPerS", replay ? 0.0 : speed},
        {"replay", replay ? parser.Get("replay") : std::string()},
        {"reachedTarget", reached},
        {"stopReason", stopReason},
        {"sessionSeconds", s.Time},
        {"wallSeconds", result.WallSeconds},
        {"realtime", run.Realtime}}},
      {"removedVolumeMm3", s.RemovedTotalMm3},
      {"removedByTissueMm3", removedByTissue},
      {"farthestRemovalFromPathMm", farthest},
      {"servoTickP50Us", result.TickCompute.P50Us},
      {"servoTickP99Us", result.TickCompute.P99Us},
      {"servoTickMaxUs", result.TickCompute.MaxUs},
      {"ticks", result.Ticks},
      {"dirtyBlockRecontourP95Ms", NearestRankPercentile(contourMs, 0.95)},
      {"dirtyBlocksPerFrameMean", meanBlocks},
      {"meshAssembleP95Ms", NearestRankPercentile(assembleMs, 0.95)},
      {"displayFrames", result.Frames.size()},
      {"wholeBoneRecontourMs", wholeMs},
      {"wholeBoneTriangles", whole.TriangleCount()},
      {"peakForceN", peak},
      {"meanCuttingForceN", cuttingTicks ? cuttingForce / cuttingTicks : 0.0},
      {"clampedTicks", clamped},
      {"protected",
       {{"segments", parser.GetAll("protect")},
        {"refusedTicks", s.RefusedTicks},
        {"stopped", s.Stopped},
        {"closestApproachMm", std::isfinite(s.ClosestApproach) ? nlohmann::json(s.ClosestApproach) : nlohmann::json(nullptr)}}}};
  doc["servo"] = ServoJson(result, run);
  if (block) {
    bool exact = false;
    const double expected = CapsuleVolumeInBox(from, reached ? to : s.Proxy, radius, blockLo, blockHi, exact);
    doc["expectedVolumeMm3"] = expected;
    doc["expectedMethod"] = exact ? "analytic: pi r^2 L + 4/3 pi r^3" : "numerical: the capsule inside the block";
    doc["volumeErrorPercent"] = expected > 0 ? 100.0 * (s.RemovedTotalMm3 - expected) / expected : 0.0;
  }
  // ---- outputs
  nlohmann::json outputs = nlohmann::json::object();
  if (!run.RecordPath.empty()) outputs["recording"] = run.RecordPath;
  if (parser.Has("model")) {
    if (!WriteModelFile(parser.Get("model"), mesh, error)) {
      err << "roboplan drill: " << error << "\n";
      return 1;
    }
    outputs["model"] = parser.Get("model");
  }
  if (parser.Has("picture")) {
    TunnelPicture picture;
    picture.Bone = mesh;
    picture.Volume = bone.get();
    picture.Materials = materials;
    picture.From = from;
    picture.To = to;
    picture.Radius = radius;
    for (const DrillRecordLine& l : result.Records) picture.Path.push_back(l.Record.Proxy);
    if (built.HasProtected) picture.Protected = TriangleMeshToPolyData(protectedMesh);
    if (!WriteTunnelPicture(parser.Get("picture"), picture, error)) {
      err << "roboplan drill: " << error << "\n";
      return 1;
    }
    outputs["picture"] = parser.Get("picture");
  }
  doc["outputs"] = outputs;
  progress.Report(1.0, "done");
  if (json) {
    out << doc.dump(2) << "\n";
  } else {
    char line[512];
    std::snprintf(line, sizeof line, "bone: %s at %.2f mm, %zu blocks (%.1f MB), built in %.2f s\n",
                  block ? "block" : parser.Get("segmentation").c_str(), voxel, built.StoredBlocks, built.MemoryMB, built.Seconds);
    out << line;
    std::snprintf(line, sizeof line, "stroke: %.2f mm with a %.2f mm burr, %s after %.2f s\n", length, radius,
                  stopReason.c_str(), s.Time);
    out << line;
    std::snprintf(line, sizeof line, "removed: %.2f mm^3", s.RemovedTotalMm3);
    out << line;
    for (size_t m = 0; m < materials.size(); ++m)
      if (s.RemovedMm3[m] > 0) {
        std::snprintf(line, sizeof line, ", %s %.2f", materials[m].Tissue.c_str(), s.RemovedMm3[m]);
        out << line;
      }
    if (block) {
      std::snprintf(line, sizeof line, " (expected %.2f, %+.2f %%)", doc["expectedVolumeMm3"].get<double>(),
                    doc["volumeErrorPercent"].get<double>());
      out << line;
    }
    out << "\n";
    std::snprintf(line, sizeof line, "servo tick: p50 %.1f us, p99 %.1f us over %llu ticks\n", result.TickCompute.P50Us,
                  result.TickCompute.P99Us, static_cast<unsigned long long>(result.Ticks));
    out << line;
    out << "servo load: " << MachineLoadSummary(result.Load) << "\n";
    std::snprintf(line, sizeof line, "display: %zu frames, dirty-block re-contour p95 %.2f ms (%.1f blocks), whole bone %.1f ms\n",
                  result.Frames.size(), NearestRankPercentile(contourMs, 0.95), meanBlocks, wholeMs);
    out << line;
    std::snprintf(line, sizeof line, "force: peak %.2f N, clamped %zu ticks\n", peak, clamped);
    out << line;
    if (built.HasProtected) {
      std::snprintf(line, sizeof line, "protected: closest approach %.2f mm, %s\n", s.ClosestApproach,
                    s.Stopped ? "the burr was stopped there" : "not reached");
      out << line;
    }
  }
  return 0;
}

}  // namespace rp
