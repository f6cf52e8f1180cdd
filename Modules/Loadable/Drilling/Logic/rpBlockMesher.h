#pragma once
// The display surface of a drillable bone, one block at a time: marching cubes (VTK's case
// table, vtkMarchingCubesTriangleCases) at density ½ over the cells each 8³ block owns (the cells
// whose lowest corner is in the block), vertices interpolated along the edges, normals from the
// density gradient (central differences, so neighbouring blocks shade without seams), and each
// vertex's material (of the edge's bone end). Only dirty blocks are re-contoured; the mesh is
// kept per block so a frame redoes a handful of blocks, never the whole bone.
// The whole bone (the first frame, a reset, an undo that touches most blocks) is contoured on
// VTK's SMP threads (vtkSMPTools, as vtkFlyingEdges3D), after one pass that finds the blocks no
// surface crosses (all bone or all empty, with the neighbours their cells reach into) and skips them;
// many dirty blocks of a frame go parallel too, each checked on its own (no pass over the volume).
// Reads densities with relaxed atomics, so the servo thread may carve meanwhile; the calls of
// one BlockMesher come from one thread at a time (the display thread).
#include <cstdint>
#include <memory>
#include <vector>

#include "rpDrillVolume.h"
#include "rpTriangleMesh.h"

namespace rp {

struct BlockMesh {
  std::vector<float> Points;      // x y z per vertex, RAS mm
  std::vector<float> Normals;     // unit, out of the bone
  std::vector<uint8_t> Materials; // voxel material code (0-based index + 1; 0 none) per vertex
  std::vector<uint32_t> Triangles;  // 3 per triangle, indices into this block's vertices
  size_t TriangleCount() const { return this->Triangles.size() / 3; }
};

class BlockMesher {
 public:
  explicit BlockMesher(DrillVolume& volume);  // consumes its dirty marks
  ~BlockMesher();
  BlockMesher(const BlockMesher&) = delete;
  BlockMesher& operator=(const BlockMesher&) = delete;
  /// Re-contours the blocks the servo thread marked dirty; returns how many. A handful (a
  /// frame of drilling) on this thread; many (a reset, an undo) as ContourAll does.
  size_t UpdateDirty();
  /// Contours every block (the first frame, or after a reset of the cache), in parallel.
  void ContourAll();
  /// Contours one block into its cache entry, on this thread.
  void Contour(int32_t slot);
  const std::vector<BlockMesh>& Blocks() const { return this->Cache; }
  size_t TriangleCount() const;
  size_t PointCount() const;
  /// Signed volume (mm³) enclosed by the cached triangles (divergence theorem; > 0 when the
  /// triangles face out of the bone).
  double EnclosedVolume() const;

  /// Dirty blocks from which UpdateDirty goes parallel (below it, threads cost more than they give).
  static constexpr size_t ParallelBlocks = 64;

 private:
  struct Scratch;  // one block's samples and edge vertices (one per thread)
  struct ThreadScratches;
  /// Contours these slots on VTK's SMP threads, skipping the blocks no surface crosses.
  void ContourSlots(const int32_t* slots, size_t count);
  uint8_t BlockSide(int32_t slot) const;  // 0 all empty, 1 all bone, 2 both (a missing slot: 0)
  void ClassifyBlocks();                  // fills Sides
  template <class SideOf>
  bool CrossesNoSurface(int32_t slot, SideOf sideOf) const;
  void ContourBlock(int32_t slot, Scratch& scratch);

  DrillVolume& Volume;
  std::vector<BlockMesh> Cache;
  std::unique_ptr<Scratch> Own;  // the calling thread's scratch
  std::unique_ptr<ThreadScratches> Scratches;  // the SMP threads' scratches
  std::vector<int32_t> Slots;    // dirty slots of one UpdateDirty (reserved: no allocation)
  std::vector<uint8_t> Sides;    // per slot: 0 all empty, 1 all bone, 2 both
};

/// The ½ iso-surface of a whole volume as one triangle mesh (every block contoured): the
/// protected structure's surface for the distance read-out.
TriangleMesh ContourToTriangleMesh(DrillVolume& volume);

}  // namespace rp
