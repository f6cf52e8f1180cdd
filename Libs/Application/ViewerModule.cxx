// The viewer as a module (lib/roboplan-modules/libRoboPlanModuleViewer.so): `roboplan` without a
// command or with data files, and `roboplan screenshot`, load it as they load any module. It holds
// no Qt and no rendering: the window and the screenshot's drawing load libRoboPlanViewer.so when
// they start (Libs/Viewer/rpViewerCommands.h), so `roboplan modules` and `screenshot --help` map
// neither. It exports roboplan_run_viewer, which roboplanMain.cxx calls once every module is set up.
#include <iostream>
#include <string>
#include <vector>

#include "rpModule.h"
#include "rpModuleManager.h"
#include "rpViewerCommands.h"
#ifdef ROBOPLAN_VIEWER_HAVE_DICOM
#include "rpImagingReaders.h"
#endif

namespace {

class ViewerModule : public rp::Module {
 public:
  std::string Name() const override { return "Viewer"; }
  std::string Title() const override { return "Viewer"; }
  void Setup(vtkRPScene*) override {
#ifdef ROBOPLAN_VIEWER_HAVE_DICOM
    rp::RegisterImagingReaders();  // File menu, drops and `roboplan <DICOM folder>` (rpDataLoader.h)
#endif
  }
  std::vector<rp::Command> Commands() override { return rp::ViewerCommands(); }
};

}  // namespace

ROBOPLAN_DECLARE_MODULE(ViewerModule)

/// The Qt main window on `scene` with every module's panel (rp::RunViewer, in libRoboPlanViewer.so).
extern "C" __attribute__((visibility("default"))) int roboplan_run_viewer(int argc, char* argv[], rp::ModuleManager* manager,
                                                                         vtkRPScene* scene,
                                                                         const std::vector<std::string>* files) {
  return rp::LaunchViewer(argc, argv, *manager, scene, *files, std::cerr);
}
