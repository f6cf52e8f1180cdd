#pragma once
// Entry points of the viewer for the `roboplan` executable:
//  - RunViewer: the Qt main window on the scene, with the files given on the command line loaded;
//  - ViewerCommands: `roboplan screenshot <scene/data files, DICOM folders...> --out <png>
//    [--layout 4up|3d|axial|sagittal|coronal] [--size WxH] [--slice-point R,A,S]` (headless).
#include <string>
#include <vector>

#include "rpBackgroundRead.h"
#include "rpModule.h"

class vtkRPScene;

namespace rp {

class ModuleManager;

int RunViewer(int argc, char* argv[], ModuleManager& manager, vtkRPScene* scene, const std::vector<std::string>& files);

std::vector<rp::Command> ViewerCommands();

/// The read of a data file or a DICOM series folder as a BackgroundRead (rp::ReadPath: nodes
/// made, not added to the scene); it may run on any thread. A path whose DataReader
/// ReadsIntoScene (a scene file: loading it changes the scene as it goes) is not read: the
/// result is LeftToMainThread (LoadSceneOrDataFile reads it there). `dicomObject`: for a DICOM
/// folder, the one object to read (an image stack's ID, a SEG's or RTSTRUCT's
/// SeriesInstanceUID, as ReadOptions::Series); empty: all it holds.
BackgroundRead MakeDataRead(vtkRPScene* scene, const std::string& path, const std::string& dicomObject = {});

/// Loads a scene file (*.rpscene, *.mrml, *.mrb), a data file or a DICOM series folder into the scene (rp::LoadPath). Problems that did not stop the
/// load (e.g. one missing data file of a scene) go to `warnings`. False with `error` on failure.
bool LoadSceneOrDataFile(vtkRPScene* scene, const std::string& path, std::string& error,
                         std::vector<std::string>* warnings = nullptr);

}  // namespace rp
