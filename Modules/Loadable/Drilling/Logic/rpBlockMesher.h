#pragma once
// The display surface of a drillable bone, one block at a time: marching cubes (VTK's case
// table, vtkMarchingCubesTriangleCases) at density ½ over the cells each 8³ block owns (the cells
// whose lowest corner is in the block), vertices interpolated along the edges, normals from the
// density gradient (central differences, so neighbouring blocks shade without seams), and each
// vertex's material (of the edge's bone end). Only dirty blocks are re-contoured; the mesh is
// kept per block so a frame redoes a handful of blocks, never the whole bone.
// Used on the display thread (or any one thread): reads densities with relaxed atomics.
#include <cstdint>
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
  /// Re-contours the blocks the servo thread marked dirty; returns how many.
  size_t UpdateDirty();
  /// Contours every block (the first frame, or after a reset of the cache).
  void ContourAll();
  /// Contours one block into its cache entry.
  void Contour(int32_t slot);
  const std::vector<BlockMesh>& Blocks() const { return this->Cache; }
  size_t TriangleCount() const;
  size_t PointCount() const;
  /// Signed volume (mm³) enclosed by the cached triangles (divergence theorem; > 0 when the
  /// triangles face out of the bone).
  double EnclosedVolume() const;

 private:
  DrillVolume& Volume;
  std::vector<BlockMesh> Cache;
  std::vector<float> Field;          // (Edge + 3)³ densities around the block being contoured
  std::vector<int32_t> EdgeVertex;   // vertex of each (corner, axis) in the block, −1 none
};

/// The ½ iso-surface of a whole volume as one triangle mesh (every block contoured): the
/// protected structure's surface for the distance read-out.
TriangleMesh ContourToTriangleMesh(DrillVolume& volume);

}  // namespace rp
