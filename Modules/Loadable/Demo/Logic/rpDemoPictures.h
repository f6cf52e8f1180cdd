#pragma once
// The demo's pictures (the bones from two sides and the 4-up views, which render a scene; the CT
// re-sliced at the tracked tip, a PNG of an image) are drawn by libRoboPlanDemoPictures.so
// (Pictures/), which links VTK's rendering, its image writers and the viewer; the demo's logic
// resolves its entries when it draws (rp::SiblingLibraryFunction), so `roboplan demo --help` and
// `roboplan modules` map neither Qt nor the rendering stack nor VTK's image codecs. The entries'
// names and types, and what they draw, in one place for both sides.
#include <array>
#include <string>
#include <vector>

class vtkImageData;
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

/// An image slice (one component) windowed to grey levels, as the viewer's slice views show it;
/// drawn without rendering (no display needed).
struct Slice {
  vtkImageData* Image = nullptr;
  double Window = 400, Level = 40;
};

/// roboplan_demo_bone_views / roboplan_demo_four_up / roboplan_demo_slice: the picture into the
/// PNG `path`; false with `error`.
using BoneViewsFunction = bool (*)(const BoneViews&, const std::string& path, std::string& error);
constexpr const char* BoneViewsEntry = "roboplan_demo_bone_views";
using FourUpFunction = bool (*)(const FourUp&, const std::string& path, std::string& error);
constexpr const char* FourUpEntry = "roboplan_demo_four_up";
using SliceFunction = bool (*)(const Slice&, const std::string& path, std::string& error);
constexpr const char* SliceEntry = "roboplan_demo_slice";

}  // namespace rp::demo_pictures
