#pragma once
// Tissue materials for haptic rendering (Resources/Materials/materials.json): stiffness, damping
// and friction per tissue class, and for the tissues a burr can cut (Drilling module) their
// hardness and the lowest CT value that classifies a bone voxel as that tissue. Loaded on the
// main thread; the servo thread reads copies.
#include <limits>
#include <string>
#include <vector>

namespace rp {

struct Material {
  std::string Tissue;
  double Stiffness = 0.5;        // N/mm
  double Damping = 0.0005;       // N·s/mm
  double StaticFriction = 0.0;   // tan of the static friction cone half-angle
  double DynamicFriction = 0.0;  // ≤ StaticFriction
  double Hardness = 0.0;         // resistance to a burr, relative to cortical bone (1); 0: not drillable
  /// Lowest CT value (HU) of a drillable bone voxel of this tissue; NaN: not classified by CT.
  double CTMinHU = std::numeric_limits<double>::quiet_NaN();
  bool Drillable() const { return this->Hardness > 0; }
};

class MaterialTable {
 public:
  /// Reads a materials.json. Returns false and names the problem (file, entry, field).
  bool Load(const std::string& path, std::string& error);
  /// The built-in table (same values as Resources/Materials/materials.json), for tests and
  /// when no file is given.
  static MaterialTable Defaults();
  /// Index of the tissue class (case-insensitive), or -1.
  int Find(const std::string& tissue) const;
  /// Index used for an empty/unknown tissue class.
  int DefaultIndex() const { return this->Default; }
  const std::vector<Material>& Materials() const { return this->Entries; }
  void Add(const Material& m) { this->Entries.push_back(m); }

 private:
  std::vector<Material> Entries;
  int Default = 0;
};

}  // namespace rp
