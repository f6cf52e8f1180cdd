// The Drilling module's panel plugin (libRoboPlanPanelDrilling.so): the viewer loads it when it shows
// the panel (Libs/ModuleCore/rpModule.h); the module's commands never load Qt.
#include "qRPDrillingPanel.h"
#include "rpModule.h"
#include "vtkRPDrillingLogic.h"

ROBOPLAN_MODULE_PANEL_EXPORT QWidget* roboplan_create_module_panel(vtkObject* logic, vtkRPScene*, QWidget* parent) {
  return new qRPDrillingPanel(vtkRPDrillingLogic::SafeDownCast(logic), parent);
}
