#pragma once
// Entry points of the viewer for the `roboplan` executable: RunViewer, the Qt main window on the
// scene, with the files given on the command line loaded. The executable reaches it, and the
// drawing of `roboplan screenshot`, through this library's extern "C" entries (rpViewerEntries.h)
// from the light side, rpViewerCommands.h, which also holds the screenshot command.
#include <string>
#include <vector>

#include "rpBackgroundRead.h"
#include "rpModule.h"
#include "rpViewerCommands.h"

class vtkRPScene;

namespace rp {

class ModuleManager;

int RunViewer(int argc, char* argv[], ModuleManager& manager, vtkRPScene* scene, const std::vector<std::string>& files);

/// The read of a data file or a DICOM series folder as a BackgroundRead (rp::ReadPath: nodes
/// made, not added to the scene); it may run on any thread. A path whose DataReader
/// ReadsIntoScene (a scene file: loading it changes the scene as it goes) is not read: the
/// result is LeftToMainThread (LoadSceneOrDataFile reads it there). `dicomObject`: for a DICOM
/// folder, the one object to read (an image stack's ID, a SEG's or RTSTRUCT's
/// SeriesInstanceUID, as ReadOptions::Series); empty: all it holds.
BackgroundRead MakeDataRead(vtkRPScene* scene, const std::string& path, const std::string& dicomObject = {});

}  // namespace rp
