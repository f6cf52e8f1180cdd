#pragma once
// Tissue materials for haptic rendering: stiffness, damping and friction per tissue class.
// Resources/Materials/materials.json is the only table: programs read it through
// LoadMaterialTable(), and the built-in table is that same file compiled in (used when the file
// cannot be found, and by tests). Tissues a burr can cut (Drilling module) also carry their
// hardness and the lowest CT value of a bone voxel of that tissue. Loaded on the main thread;
// the servo thread reads copies.
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
  /// Parses the text of a materials.json; `source` names it in messages.
  bool Parse(const std::string& text, const std::string& source, std::string& error);
  /// Resources/Materials/materials.json as it was when the program was built.
  static MaterialTable Defaults();
  /// Index of the tissue class (case-insensitive), or -1.
  int Find(const std::string& tissue) const;
  /// Index used for an empty/unknown tissue class.
  int DefaultIndex() const { return this->Default; }
  const std::vector<Material>& Materials() const { return this->Entries; }
  /// The tissue class names, in the file's order (for tissue pickers).
  std::vector<std::string> TissueNames() const;
  bool Empty() const { return this->Entries.empty(); }
  /// Where the table came from (a path, or the built-in copy).
  const std::string& Source() const { return this->Origin; }
  /// Tests build small tables by hand.
  void Add(const Material& m) { this->Entries.push_back(m); }

 private:
  std::vector<Material> Entries;
  int Default = 0;
  std::string Origin;
};

/// The one way programs (viewer, CLI, demo, panels) get the tissue table: `path` when given,
/// else Resources/Materials/materials.json (rp::ResourcePath). Only when that file does not
/// exist is the built-in copy used (Source() says so). A file that exists but is broken is an
/// error, never silently replaced.
bool LoadMaterialTable(MaterialTable& table, std::string& error, const std::string& path = std::string());

}  // namespace rp
