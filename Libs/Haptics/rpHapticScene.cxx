#include "rpHapticScene.h"

namespace rp {

std::unique_ptr<HapticScene> HapticScene::Build(const std::vector<HapticMeshInput>& meshes, const MaterialTable& table,
                                                std::vector<std::string>& warnings, std::string& error) {
  auto scene = std::make_unique<HapticScene>();
  scene->Materials = table.Materials();
  if (scene->Materials.empty()) {
    error = "haptic scene: the material table is empty";
    return nullptr;
  }
  for (const HapticMeshInput& input : meshes) {
    std::string meshError;
    if (!input.Mesh.Validate(meshError)) {
      error = "haptic scene: model '" + input.Name + "': " + meshError;
      return nullptr;
    }
    int material = table.Find(input.TissueClass);
    if (material < 0) {
      material = table.DefaultIndex();
      warnings.push_back("model '" + input.Name + "': tissue class '" + input.TissueClass +
                         "' is not in the material table; using '" + scene->Materials[material].Tissue + "'");
    }
    scene->Mesh.Append(input.Mesh, static_cast<uint16_t>(material));
    scene->MeshNames.push_back(input.Name);
  }
  scene->Mesh.ComputeNormals();
  scene->Tree.Build(scene->Mesh);
  return scene;
}

}  // namespace rp
