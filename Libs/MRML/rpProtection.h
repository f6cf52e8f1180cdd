#pragma once
// A structure at risk: a model or a segment flagged "protected", with the safety margin (mm) a
// planned tool and a burr must keep from its surface. The one notion planning, drilling and
// guidance read (DESIGN.md, "Plans and guidance"); it lives on the model node
// (vtkRPModelNode::GetProtection) or on the segment (rp::Segment::Protection) and nowhere else.
//
// Stored as: model properties and MRML attributes "RoboPlan.protected" / "RoboPlan.safetyMarginMm";
// segments' .seg.nrrd tags "RoboPlan.Protected" / "RoboPlan.SafetyMarginMm" (beside
// "RoboPlan.TissueClass"); the .rpscene segment table "protected" / "safetyMarginMm".
#include <map>
#include <string>

namespace rp {

struct StructureProtection {
  bool Protected = false;
  double SafetyMarginMm = 0.0;  // >= 0; meaningful only when Protected
  bool operator==(const StructureProtection& o) const {
    return this->Protected == o.Protected && this->SafetyMarginMm == o.SafetyMarginMm;
  }
  bool operator!=(const StructureProtection& o) const { return !(*this == o); }
};

/// The keys, in the one spelling each format uses.
constexpr const char* ProtectedKey = "protected";
constexpr const char* SafetyMarginKey = "safetyMarginMm";
constexpr const char* ProtectedSegmentTag = "RoboPlan.Protected";
constexpr const char* SafetyMarginSegmentTag = "RoboPlan.SafetyMarginMm";

/// Writes the two keys into a key/value map (nothing when not protected, so files of unprotected
/// structures stay as they were); reads them back. `ReadProtection` ignores a margin that is not
/// a finite number >= 0 (the structure stays protected, with margin 0) and says so in `warning`.
void WriteProtection(const StructureProtection& protection, std::map<std::string, std::string>& out,
                     const std::string& protectedKey, const std::string& marginKey);
StructureProtection ReadProtection(const std::map<std::string, std::string>& in, const std::string& protectedKey,
                                        const std::string& marginKey, std::string* warning = nullptr);

}  // namespace rp
