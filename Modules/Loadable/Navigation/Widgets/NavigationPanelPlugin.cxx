// The Navigation module's panel plugin (libRoboPlanPanelNavigation.so): the viewer loads it when it shows
// the panel (Libs/ModuleCore/rpModule.h); the module's commands never load Qt.
#include "qRPNavigationPanel.h"
#include "rpModule.h"
#include "vtkRPNavigationLogic.h"

ROBOPLAN_MODULE_PANEL_EXPORT QWidget* roboplan_create_module_panel(vtkObject* logic, vtkRPScene*, QWidget* parent) {
  return new qRPNavigationPanel(vtkRPNavigationLogic::SafeDownCast(logic), parent);
}
