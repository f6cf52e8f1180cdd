#pragma once
// The viewer's side that needs no Qt and no rendering (library RoboPlanViewerCommands): the Viewer
// module links it, so `roboplan screenshot --help` and `roboplan modules` map neither. Opening the
// window and drawing load libRoboPlanViewer.so then (rpViewerEntries.h).
//  - ViewerCommands: `roboplan screenshot <scene/data files, DICOM folders...> --out <png>
//    [--layout 4up|3d|axial|sagittal|coronal] [--size WxH] [--slice-point R,A,S]` (headless);
//  - LaunchViewer: rp::RunViewer (rpViewerApplication.h) through libRoboPlanViewer.so.
#include <string>
#include <vector>

#include "rpModule.h"

class vtkRPScene;

namespace rp {

class ModuleManager;

std::vector<rp::Command> ViewerCommands();

/// The Qt main window on `scene` with every module's panel; 1 with a message on `err` naming the
/// library when the viewer cannot be loaded.
int LaunchViewer(int argc, char* argv[], ModuleManager& manager, vtkRPScene* scene, const std::vector<std::string>& files,
                 std::ostream& err);

/// Loads a scene file (*.rpscene, *.mrml, *.mrb), a data file or a DICOM series folder into the scene (rp::LoadPath). Problems that did not stop the
/// load (e.g. one missing data file of a scene) go to `warnings`. False with `error` on failure.
bool LoadSceneOrDataFile(vtkRPScene* scene, const std::string& path, std::string& error,
                         std::vector<std::string>* warnings = nullptr);

}  // namespace rp
