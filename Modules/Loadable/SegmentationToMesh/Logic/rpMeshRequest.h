#pragma once
// `roboplan mesh`, part 1: its options (declared once: --help, the parser's checks and the
// --xml/--boutiques descriptors come from them) and what they ask for, as the logic takes it.
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "rpArgParser.h"
#include "rpBoneSplit.h"
#include "rpDataLoader.h"
#include "rpLabelmapInput.h"
#include "rpSegmentationToModels.h"
#include "vtkRPSegmentationToMeshLogic.h"

namespace rp {

struct MeshRequest {
  std::string Input, Labels, Truth, Format;  // Labels, Truth: "" when not given
  std::filesystem::path OutDir;
  bool Json = false;
  ReadOptions Read;
  // A volume: labelmap or intensity image (rpLabelmapInput.h's rule; IntensityOptions: a
  // threshold or method option was given).
  InputKind Kind = InputKind::Auto;
  bool IntensityOptions = false;
  // --split-bones: the bones one by one (seeds: --bone-seed, parsed when the bones are split,
  // and --seed).
  bool SplitBones = false;
  BoneSplitOptions Bones;
  std::vector<std::string> BoneSeeds;
  // Else one segment per tissue: the presets (one range with --lower/--upper), each found by
  // Method and then edited by Edits in order.
  std::vector<std::string> Presets;
  std::optional<double> Lower, Upper;
  SegmentMethod Method;
  double MaxFraction = 0.9;
  std::vector<SegmentEdit> Edits;
  // The surfaces (GridMm: a contour grid in mm instead of Build's grid step).
  ModelBuildOptions Build;
  std::optional<double> GridMm;
};

void DeclareMeshOptions(ArgParser& parser);
/// What the parsed options ask for. False (after naming the problem on `err`): options that
/// contradict each other (each value alone was checked by the parser).
bool ParseMeshRequest(const ArgParser& parser, MeshRequest& request, std::ostream& err);

}  // namespace rp
