#pragma once
// The demo's pictures that render a scene (the bones from two sides, the 4-up views) are drawn by
// libRoboPlanDemoPictures.so (Pictures/), which links VTK's rendering and the viewer; the demo's
// logic resolves its entries when it draws (rp::SiblingLibraryFunction), so `roboplan demo --help`
// and `roboplan modules` map neither Qt nor the rendering stack. The entries' names and types, and
// what they draw, in one place for both sides.
#include <array>
#include <string>
#include <vector>

class vtkRPScene;

#define RP_DEMO_PICTURES_ENTRY extern "C" __attribute__((visibility("default")))

namespace rp::demo_pictures {

constexpr const char* Library = "libRoboPlanDemoPictures.so";

/// The bone models alone, each in its colour, from the front and from the lateral side.
struct BoneViews {
  vtkRPScene* Scene = nullptr;
  std::vector<std::string> ModelIDs;
  std::array<double, 3> Lateral{{1, 0, 0}}, Anterior{{0, 1, 0}};  // the knee's own axes
  bool AxesKnown = false;  // else lateral is the scanner's, towards the fibula
};

/// The 4-up views (axial, 3D, sagittal, coronal) of the scene, as the viewer draws them.
struct FourUp {
  vtkRPScene* Scene = nullptr;
  std::string BackgroundID, ForegroundID;  // volumes; "" for none
  bool HasSlicePoint = false;
  std::array<double, 3> SlicePointRAS{};
  std::string FollowNodeID;  // the slices follow its origin; "" for none
};

/// roboplan_demo_bone_views / roboplan_demo_four_up: the picture into the PNG `path`; false with `error`.
using BoneViewsFunction = bool (*)(const BoneViews&, const std::string& path, std::string& error);
using FourUpFunction = bool (*)(const FourUp&, const std::string& path, std::string& error);

}  // namespace rp::demo_pictures
