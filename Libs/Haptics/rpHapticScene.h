#pragma once
// The immutable collision world of the servo loop: all haptic meshes merged into one triangle
// mesh (label = material index), its BVH and the materials. Built on the main thread (or any
// non-servo thread), then handed to the servo thread through a SceneExchange without locks.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rpBVH.h"
#include "rpHandover.h"
#include "rpMaterial.h"
#include "rpTriangleMesh.h"

namespace rp {

struct HapticMeshInput {
  std::string Name;         // model name, for messages
  std::string TissueClass;  // looked up in the material table
  TriangleMesh Mesh;        // RAS, mm
};

struct HapticScene {
  TriangleMesh Mesh;  // merged; Labels index Materials
  BVH Tree;
  std::vector<Material> Materials;
  std::vector<std::string> MeshNames;  // one per input mesh
  uint64_t Version = 0;

  /// Merges the meshes, looks up their materials (empty/unknown tissue class: the table's
  /// default, reported in `warnings`) and builds the BVH. Returns nullptr and names the
  /// problem for invalid meshes.
  static std::unique_ptr<HapticScene> Build(const std::vector<HapticMeshInput>& meshes, const MaterialTable& table,
                                            std::vector<std::string>& warnings, std::string& error);
  const Material& MaterialOf(uint32_t triangle) const { return this->Materials[this->Mesh.Label(triangle)]; }
};

/// Hands new scenes to the servo thread without locks (rpHandover.h).
using SceneExchange = Handover<HapticScene>;

}  // namespace rp
