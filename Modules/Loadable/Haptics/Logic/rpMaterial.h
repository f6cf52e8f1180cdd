#pragma once
// Tissue materials for haptic rendering (Resources/Materials/materials.json): stiffness, damping
// and friction per tissue class. Loaded on the main thread; the servo thread reads copies.
#include <string>
#include <vector>

namespace rp {

struct Material {
  std::string Tissue;
  double Stiffness = 0.5;        // N/mm
  double Damping = 0.0005;       // N·s/mm
  double StaticFriction = 0.0;   // tan of the static friction cone half-angle
  double DynamicFriction = 0.0;  // ≤ StaticFriction
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
