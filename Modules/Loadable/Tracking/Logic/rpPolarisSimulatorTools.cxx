#include "rpPolarisSimulatorTools.h"

#include <algorithm>
#include <cmath>

namespace rp {

void PolarisSimulatorTools::Add(const ToolDefinition& tool, int wiredPort) {
  auto runtime = std::make_unique<Tool>();
  runtime->Definition = tool;
  runtime->WiredPort = wiredPort;
  if (runtime->Definition.Rom.empty()) runtime->Definition.Rom = rom::Build(tool.PartNumber, tool.Markers);
  std::string error;  // a ROM that does not read leaves the geometry empty: always visible
  rom::Read(runtime->Definition.Rom.data(), runtime->Definition.Rom.size(), runtime->Rom, error);
  std::lock_guard<std::mutex> lock(this->Mutex);
  this->Tools.push_back(std::move(runtime));
}

int PolarisSimulatorTools::ForRom(const std::vector<uint8_t>& image, const double volumeCenter[3]) {
  for (size_t t = 0; t < this->Tools.size(); ++t) {
    if (this->Tools[t]->WiredPort >= 0) continue;  // a wired tool is its port's, not a ROM's
    const auto& known = this->Tools[t]->Definition.Rom;
    if (known.size() <= image.size() && std::equal(known.begin(), known.end(), image.begin())) return static_cast<int>(t);
  }
  // A definition we were not given: a tool of its own, its geometry from the ROM, standing still
  // in the volume (a row of such tools 150 mm apart), as a camera tracks any tool it is sent.
  rom::Definition definition;
  std::string error;
  if (!rom::Read(image.data(), image.size(), definition, error)) return -1;
  auto runtime = std::make_unique<Tool>();
  ToolDefinition& tool = runtime->Definition;
  tool.PartNumber = definition.PartNumber;
  tool.Name = definition.PartNumber.empty() ? "ROM" + std::to_string(this->Tools.size() + 1) : definition.PartNumber;
  tool.Markers = definition.Markers;
  tool.Rom.assign(image.begin(), image.begin() + static_cast<long>(rom::Size));
  tool.Motion.Type = ToolTrajectory::Static;
  for (int k = 0; k < 3; ++k) tool.Motion.Center[k] = volumeCenter[k];
  tool.Motion.Center[0] += 150.0 * static_cast<double>(this->Tools.size()) - 300.0;
  runtime->Rom = definition;
  std::lock_guard<std::mutex> lock(this->Mutex);
  this->Tools.push_back(std::move(runtime));
  return static_cast<int>(this->Tools.size() - 1);
}

std::vector<std::string> PolarisSimulatorTools::Names() const {
  std::lock_guard<std::mutex> lock(this->Mutex);
  std::vector<std::string> names;
  for (const auto& t : this->Tools) names.push_back(t->Definition.Name);
  return names;
}

std::vector<std::array<double, 3>> PolarisSimulatorTools::Markers(const std::string& toolName) const {
  std::lock_guard<std::mutex> lock(this->Mutex);
  for (const auto& t : this->Tools)
    if (t->Definition.Name == toolName) return t->Definition.Markers;
  return {};
}

void PolarisSimulatorTools::SetOccluded(const std::string& toolName, bool occluded) {
  std::lock_guard<std::mutex> lock(this->Mutex);
  for (auto& t : this->Tools)
    if (t->Definition.Name == toolName) t->Occluded = occluded;
}

void PolarisSimulatorTools::SetOutOfVolume(const std::string& toolName, bool outOfVolume) {
  std::lock_guard<std::mutex> lock(this->Mutex);
  for (auto& t : this->Tools)
    if (t->Definition.Name == toolName) t->OutOfVolume = outOfVolume;
}

bool PolarisSimulatorTools::TruePose(const std::string& toolName, double t, double m[16]) const {
  std::lock_guard<std::mutex> lock(this->Mutex);
  for (auto& tool : this->Tools) {
    if (tool->Definition.Name == toolName) {
      EvaluateTrajectory(tool->Definition, t, m);
      return true;
    }
  }
  return false;
}

bool PolarisSimulatorTools::MarkersVisible(const Tool& tool, const double m[16]) {
  const rom::Definition& g = tool.Rom;
  if (g.Markers.empty()) return true;
  const double cosMax = std::cos(std::min(180, std::max(0, g.MaxMarkerAngleDeg)) * M_PI / 180.0);
  int visible = 0;
  for (size_t i = 0; i < g.Markers.size(); ++i) {
    const auto& p = g.Markers[i];
    const auto& nn = i < g.Normals.size() ? g.Normals[i] : rom::Vec3{0, 0, 0};
    double world[3], normal[3], distance = 0, length = 0;
    for (int r = 0; r < 3; ++r) {
      world[r] = m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3];
      normal[r] = m[4 * r] * nn[0] + m[4 * r + 1] * nn[1] + m[4 * r + 2] * nn[2];
      distance += world[r] * world[r];
      length += normal[r] * normal[r];
    }
    if (length < 1e-12) {  // no normal given: seen from everywhere
      ++visible;
      continue;
    }
    // Towards the camera (the tracker origin) is -world.
    const double facing = -(normal[0] * world[0] + normal[1] * world[1] + normal[2] * world[2]) / std::sqrt(distance * length);
    if (facing >= cosMax) ++visible;
  }
  return visible >= std::max(1, g.MinimumMarkers);
}

}  // namespace rp
