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

SceneExchange::~SceneExchange() { this->Clear(); }

void SceneExchange::Publish(std::unique_ptr<HapticScene> scene) {
  HapticScene* previous = this->Pending.exchange(scene.release(), std::memory_order_acq_rel);
  delete previous;  // never taken by the servo thread
  this->Collect();
}

void SceneExchange::Collect() { delete this->Retired.exchange(nullptr, std::memory_order_acq_rel); }

const HapticScene* SceneExchange::Acquire() noexcept {
  HapticScene* current = this->Current.load(std::memory_order_relaxed);
  if (this->Pending.load(std::memory_order_relaxed) == nullptr) return current;
  if (current != nullptr && this->Retired.load(std::memory_order_acquire) != nullptr) return current;  // wait for Collect
  HapticScene* next = this->Pending.exchange(nullptr, std::memory_order_acq_rel);
  if (next == nullptr) return current;
  if (current != nullptr) this->Retired.store(current, std::memory_order_release);
  this->Current.store(next, std::memory_order_release);
  return next;
}

void SceneExchange::Clear() {
  delete this->Pending.exchange(nullptr);
  delete this->Retired.exchange(nullptr);
  delete this->Current.exchange(nullptr);
}

}  // namespace rp
