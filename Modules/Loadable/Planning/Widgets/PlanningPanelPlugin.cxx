// The Planning module's panel plugin (libRoboPlanPanelPlanning.so): the viewer loads it when it shows
// the panel (Libs/ModuleCore/rpModule.h); the module's commands never load Qt.
#include "qRPPlanningPanel.h"
#include "rpModule.h"
#include "vtkRPPlanningLogic.h"

ROBOPLAN_MODULE_PANEL_EXPORT QWidget* roboplan_create_module_panel(vtkObject* logic, vtkRPScene*, QWidget* parent) {
  return new qRPPlanningPanel(vtkRPPlanningLogic::SafeDownCast(logic), parent);
}
