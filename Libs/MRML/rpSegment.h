#pragma once
// One segment of a segmentation, as plain data: what vtkRPSegmentationNode holds and what the
// .seg.nrrd header parser produces.
#include <string>

#include "rpProtection.h"

namespace rp {

struct Segment {
  std::string ID;           // unique within the segmentation, e.g. "femur"
  std::string Name;         // shown to users, e.g. "Femur"
  int LabelValue = 1;       // voxel value in the labelmap
  double Color[3] = {1, 1, 1};
  std::string TissueClass;  // a tissue of Resources/Materials/materials.json (bone, cartilage, ...)
  rp::StructureProtection Protection;  // a structure at risk when Protection.Protected (rpProtection.h)
};

}  // namespace rp
