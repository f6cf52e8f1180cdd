#pragma once
// The SegmentationToMesh module's CLI subcommand (headless, testable in-process):
//   roboplan mesh <volume | segmentation | labelmap> --out <dir> [options]
// segments a CT/MR (threshold presets, region growing, confidence connected, morphology,
// components) or takes a segmentation, and writes one closed surface per segment (display +
// haptic level of detail). Exit codes: 0 ok, 1 the work failed (stderr names the problem),
// 2 bad arguments.
#include <ostream>
#include <string>
#include <vector>

class vtkRPScene;

namespace rp {

/// `scene` may be null (a scene of its own is used); loaded and created nodes are added to it.
int RunMeshCommand(const std::vector<std::string>& arguments, vtkRPScene* scene, std::ostream& out,
                   std::ostream& err);

}  // namespace rp
