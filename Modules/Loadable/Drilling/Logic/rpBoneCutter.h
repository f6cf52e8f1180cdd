#pragma once
// Removes bone where the burr cuts, on the servo thread: a cut carves the burr's sphere into the
// densities (the same two-voxel ramp as the bone's surface, so the removed volume is the swept
// sphere's and nothing beyond r + one voxel changes), unless the sphere reaches a protected
// voxel: then nothing is removed at all. It counts the removed volume per material, marks the
// changed blocks dirty for the display, and keeps what each stroke changed (a copy of every
// block the first time a stroke touches it, in a fixed pool) so the last strokes can be undone;
// undo and reset are restored a few hundred blocks per tick. Never allocates after construction.
#include <cstdint>
#include <vector>

#include "rpDrillVolume.h"

namespace rp {

struct CutResult {
  bool Refused = false;   // a protected voxel is within reach: nothing removed
  bool Removed = false;   // some bone was removed
  double VolumeMm3 = 0;   // removed by this cut
};

class BoneCutter {
 public:
  struct Options {
    size_t UndoBlocks = 16384;    // pool size in blocks (512 bytes each)
    int MaxStrokes = 64;          // undoable strokes kept
    int RestoreBlocksPerTick = 256;
  };
  explicit BoneCutter(DrillVolume& volume);
  BoneCutter(DrillVolume& volume, const Options& options);

  // ---- servo thread
  /// Carves the sphere (centre, radius). Refused, removing nothing, when it reaches a protected
  /// voxel (a protected bone voxel within radius + one voxel, or any protected voxel within the
  /// radius). When the last cut was the same sphere `advance` behind the centre along `direction`
  /// (unit; zero when there was none), only what the new sphere adds is visited: voxels within
  /// r − h − advance of the centre, and those behind the bisecting plane, cannot change.
  CutResult Cut(const Vec3& center, double radius, const Vec3& direction = Vec3{}, double advance = 0) noexcept;
  /// The same cut spread over `slices` calls, so no tick carries all of it: checks the protected
  /// structure, then carves the first share of the rows (interleaved rows, so every part of the
  /// cap recedes together); ContinueCut() carves the next share. A cut still pending is finished
  /// first. Cut() is BeginCut(…, 1).
  CutResult BeginCut(const Vec3& center, double radius, const Vec3& direction, double advance, int slices) noexcept;
  /// Carves the next share of the pending cut (nothing when none is pending).
  CutResult ContinueCut() noexcept;
  bool CutPending() const { return this->Job.Next < this->Job.Slices; }
  /// Carves what is left of the pending cut now (a stroke's end, an undo).
  void FinishCut() noexcept;
  /// True when a cut at (center, radius) would be refused.
  bool ReachesProtected(const Vec3& center, double radius) const noexcept;
  void BeginStroke() noexcept;
  void EndStroke() noexcept;
  bool InStroke() const { return this->Stroking; }
  /// Starts restoring the last finished stroke (ends a stroke in progress first). False when there
  /// is none or it was too large to keep.
  bool StartUndo() noexcept;
  /// Starts restoring every block to the bone as built; forgets the strokes.
  void StartReset() noexcept;
  bool Restoring() const { return this->Mode != RestoreMode::None; }
  /// Restores up to Options::RestoreBlocksPerTick blocks of a pending undo/reset.
  void Step() noexcept;
  /// Removed volume (mm³) per material index (0-based), and in total.
  double Removed(int material) const noexcept;
  double RemovedTotal() const noexcept;
  int UndoableStrokes() const { return this->StrokeCount; }
  uint32_t StrokesStarted() const { return this->StrokeId; }
  /// The last finished stroke could not be kept (larger than the undo pool).
  bool LastStrokeLost() const { return this->Lost; }

 private:
  enum class RestoreMode { None, Undo, Reset };
  struct PendingCut {
    Vec3 Center, Lo, Hi;  // the sphere; the box of the cap its rows are limited to (RAS)
    double Radius = 0, Inner = 0;
    bool Incremental = false;
    DrillVolume::HalfSpace Ahead{};
    int Slices = 0, Next = 0;  // shares of the rows, and the next one to carve
  };
  struct Stroke {
    size_t Begin = 0, End = 0;  // pool entries [Begin, End)
    int64_t RemovedBefore[DrillVolume::MaxMaterials] = {};
    bool Kept = true;
  };
  void Snapshot(int32_t slot) noexcept;
  Stroke& StrokeAt(int fromNewest) noexcept;
  void RestoreBlock(int32_t slot, const uint8_t* data) noexcept;

  DrillVolume& Volume;
  Options Settings;
  std::vector<uint8_t> Pool;
  std::vector<int32_t> PoolSlots;
  size_t Head = 0, Tail = 0;  // pool entries in use: [Tail, Head), modulo the pool size
  std::vector<Stroke> Strokes;  // ring of MaxStrokes
  int StrokeNewest = -1, StrokeCount = 0;
  std::vector<uint32_t> Stamps;  // per block: the stroke that copied it last
  uint32_t StrokeId = 0;
  bool Stroking = false, Lost = false;
  int64_t RemovedUnits[DrillVolume::MaxMaterials] = {};  // in 1/255 of a voxel
  RestoreMode Mode = RestoreMode::None;
  PendingCut Job;
  size_t RestoreNext = 0, RestoreEnd = 0;
};

}  // namespace rp
