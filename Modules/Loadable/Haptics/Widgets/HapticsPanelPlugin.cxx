// The Haptics module's panel plugin (libRoboPlanPanelHaptics.so): the viewer loads it when it shows
// the panel (Libs/ModuleCore/rpModule.h); the module's commands never load Qt.
#include "qRPHapticsPanel.h"
#include "rpModule.h"
#include "vtkRPHapticsLogic.h"

ROBOPLAN_MODULE_PANEL_EXPORT QWidget* roboplan_create_module_panel(vtkObject* logic, vtkRPScene*, QWidget* parent) {
  return new qRPHapticsPanel(vtkRPHapticsLogic::SafeDownCast(logic), parent);
}
