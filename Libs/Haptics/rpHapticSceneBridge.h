#pragma once
// The bridge between the scene (main thread, VTK nodes) and the haptic servo loop (plain C++):
//  - haptic meshes come from model nodes flagged Haptic, in RAS, with their TissueClass;
//  - the device-to-scene transform comes from the transform node named HapticDeviceToRAS
//    (a uniform scale in its matrix is the workspace scale); a tool followed from the scene (a
//    tracked stylus's or drill's tip node) is read in RAS, as the servo takes it (rpToolInput);
//  - the servo's published state is copied into tool nodes at display rate, each inside one
//    StartModify/EndModify. The servo thread never touches a node.
#include <string>
#include <vector>

#include "rpHapticServo.h"

class vtkMatrix4x4;
class vtkRPScene;

namespace rp {

constexpr const char* HapticDeviceToRASName = "HapticDeviceToRAS";
constexpr const char* HapticInterfacePointName = "HapticInterfacePoint";  // tool node: HIP pose in RAS
constexpr const char* HapticProxyName = "HapticProxy";  // tool node: proxy; attributes Force, Tissue, Contact

/// The haptic models of the scene. Models without polygons are skipped with a warning.
std::vector<HapticMeshInput> CollectHapticMeshes(vtkRPScene* scene, std::vector<std::string>& warnings);

/// A number that changes whenever a haptic model, its mesh or its transforms change.
unsigned long HapticMeshesSignature(vtkRPScene* scene);

/// Reads the HapticDeviceToRAS node; false (and identity) when the scene has none.
bool ReadDeviceToScene(vtkRPScene* scene, DeviceToScene& transform);

/// The pose of a 4x4 rigid matrix (rotation and translation; no scale expected).
Pose PoseFromMatrix(const vtkMatrix4x4* matrix);

/// The world (RAS) pose of a transformable node whose origin is the tool's tip, e.g. a tracked
/// stylus's StylusTipToStylus under StylusToTracker under TrackerToRAS: what a servo following a
/// tracked tool takes (ToolInput::SetPosesInScene). False when no such node.
bool ReadToolPose(vtkRPScene* scene, const std::string& nodeID, Pose& stylusToRAS);

/// Copies the state into the HapticInterfacePoint and HapticProxy tool nodes (created when
/// missing). `labelNames[i]` is material i's tissue name.
void UpdateToolNodes(vtkRPScene* scene, const HapticState& state, const std::vector<std::string>& labelNames);

}  // namespace rp
