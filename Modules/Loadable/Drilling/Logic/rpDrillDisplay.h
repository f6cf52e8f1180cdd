#pragma once
// The drilled bone on screen at display rate without re-contouring the bone: a display thread
// (30 Hz) re-contours only the blocks the servo thread marked dirty (rpBlockMesher), then
// assembles the cached block meshes into a new vtkPolyData (points, normals, the "Material"
// point array, triangles) and posts it; the main thread takes it and swaps it into the model
// node (one pointer swap). The bone as a whole is contoured once, at the start.
#include <atomic>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <vtkSmartPointer.h>

#include "rpBlockMesher.h"

class vtkPolyData;

namespace rp {

struct DisplayFrame {
  size_t Blocks = 0;         // blocks re-contoured in this frame (0: PostMesh's assembly only)
  double ContourMs = 0;      // re-contouring those blocks
  double AssembleMs = 0;     // building the model's polydata from the block meshes
  size_t Triangles = 0;
};

/// A run's display timings: the frames that re-contoured blocks, and the mesh assemblies (every
/// such frame's, or PostMesh's one).
struct DisplayTimings {
  std::vector<double> ContourMs, Blocks, AssembleMs;
};
DisplayTimings SplitDisplayFrames(const std::vector<DisplayFrame>& frames);

/// Nearest-rank percentile (q in 0–1) of a run's timings, e.g. the frames' re-contour ms; 0 when empty.
double NearestRankPercentile(std::vector<double> values, double q);

class DrillDisplay {
 public:
  explicit DrillDisplay(DrillVolume& volume);
  ~DrillDisplay();
  DrillDisplay(const DrillDisplay&) = delete;
  DrillDisplay& operator=(const DrillDisplay&) = delete;

  /// Contours the whole bone (once, before the threads start) and returns its mesh.
  vtkSmartPointer<vtkPolyData> Initialize();
  /// One frame: re-contours the dirty blocks; when any changed and meshes are posted every
  /// frame, assembles and posts the mesh. Called by the display thread, or by the caller in
  /// scripted runs.
  DisplayFrame Frame();
  /// Whether Frame() assembles and posts the mesh (the default) or only keeps the block meshes
  /// current, for a scripted run whose caller wants only the last mesh (PostMesh): the assembly
  /// writes the whole bone's mesh (23 MB for a 40 mm block at 0.2 mm), which on the servo's own
  /// thread evicts the servo's data from the cache every 33rd tick.
  void SetMeshEveryFrame(bool every) { this->MeshEveryFrame = every; }
  /// Assembles the block meshes as they are and posts them (recorded as a frame of no blocks).
  void PostMesh();
  /// Re-contours the blocks a change before a run dirtied (the burr placed cutting: part of the
  /// bone the run starts from), outside the frames and their figures.
  size_t CatchUp() { return this->Blocks.UpdateDirty(); }
  /// Runs Frame() at `rateHz` on a display thread.
  bool Start(double rateHz, std::string& error);
  void Stop();
  bool Running() const { return this->Thread.joinable(); }
  /// Main thread: the newest posted mesh (nullptr when nothing new since the last call).
  vtkSmartPointer<vtkPolyData> TakeMesh();
  /// Frames that re-contoured something (a copy, any thread).
  std::vector<DisplayFrame> Frames() const;
  const BlockMesher& Mesher() const { return this->Blocks; }

  /// The cached block meshes as one polydata (what Frame() posts).
  static vtkSmartPointer<vtkPolyData> Assemble(const BlockMesher& mesher);

 private:
  vtkSmartPointer<vtkPolyData> AssembleInto(DisplayFrame& frame) const;  // timed, into frame

  BlockMesher Blocks;
  std::thread Thread;
  std::atomic<bool> StopRequested{false};
  bool MeshEveryFrame = true;
  mutable std::mutex Lock;  // guards Pending and History (display ↔ main; never the servo)
  vtkSmartPointer<vtkPolyData> Pending;
  std::vector<DisplayFrame> History;
};

}  // namespace rp
