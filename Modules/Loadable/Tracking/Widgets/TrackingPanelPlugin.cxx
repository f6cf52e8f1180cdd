// The Tracking module's panel plugin (libRoboPlanPanelTracking.so): the viewer loads it when it shows
// the panel (Libs/ModuleCore/rpModule.h); the module's commands never load Qt.
#include "qRPTrackingPanel.h"
#include "rpModule.h"
#include "vtkRPTrackingLogic.h"

ROBOPLAN_MODULE_PANEL_EXPORT QWidget* roboplan_create_module_panel(vtkObject* logic, vtkRPScene*, QWidget* parent) {
  return new qRPTrackingPanel(vtkRPTrackingLogic::SafeDownCast(logic), parent);
}
