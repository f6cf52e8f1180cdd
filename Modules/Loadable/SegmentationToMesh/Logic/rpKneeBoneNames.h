#pragma once
// Names of knee bones from their position and size (RAS), and a colour per bone name.
#include <array>
#include <string>
#include <vector>

#include "rpBoneSplit.h"

namespace rp {

/// Gives the unnamed bones of a knee CT their names (femur, tibia, fibula, patella) when the
/// anatomy is recognisable; bones already named (by seeds) keep theirs and are used as
/// landmarks. `ctBounds`: RAS bounds of the CT (bones cut by the field of view are judged by
/// what is inside it).
void NameKneeBones(std::vector<BoneInfo>& bones, const double ctBounds[6]);

/// A colour for a bone: a knee bone's (femur, tibia, fibula, patella, also "tibia left") from
/// rp::KneeBones(), the one bone colour table; others DefaultLabelColor(labelValue).
std::array<double, 3> BoneColor(const std::string& name, int labelValue);
/// The knee bone colour for `name` (see BoneColor); false when it names no knee bone.
bool KneeBoneColor(const std::string& name, std::array<double, 3>& color);

}  // namespace rp
